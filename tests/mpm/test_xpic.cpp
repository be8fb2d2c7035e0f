// XPIC(m) velocity update (Hammerquist & Nairn 2017). With A = S F S+ (grid round trip of the
// particle velocities: mass-weighted map to the nodes S+, the boundary conditions F, interpolation
// back S), a step without forces gives the particles V^1 = [1 - (1 - A)^m] V^0 with pure XPIC(m)
// (flip fraction 0). The reference here applies A by its own loops over the shape functions, m
// times in product form, while the solver sums the binomial series on the grid; m = 1 is PIC.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

struct XpicModel {
  Grid grid;
  Particles particles;
};

// 6 x 5 cells, particles in a block that touches the fixed left side, with velocities that are
// neither smooth nor resolved by the grid (so that every order filters differently).
XpicModel make_setup() {
  XpicModel s{Grid(GridAxis::uniform(0.0, 1.2, 6), GridAxis::uniform(0.0, 1.0, 5)), Particles{}};
  s.grid.set_boundary(Side::left, BoundaryCondition::fixed);
  s.grid.set_boundary(Side::bottom, BoundaryCondition::roller);
  s.particles = test_support::particle_block(s.grid, Geometry::plane_strain,
                                             test_support::block_fill(0.0, 1.0, 0.0, 0.8, 2000.0));
  for (std::size_t p = 0; p < s.particles.size(); ++p) {
    const double k = static_cast<double>(p);
    s.particles.velocity[p] = Vec2(0.3 + std::sin(1.7 * k), -0.2 + std::cos(2.3 * k * k));
  }
  return s;
}

// A V: the particle velocities mapped to the nodes with mass weights, held at the constrained
// node components, and interpolated back, all with the cpGIMP stencils at the particles' places.
std::vector<Vec2> round_trip(const Grid& grid, const Particles& particles,
                             const std::vector<Vec2>& velocity) {
  const auto nodes = static_cast<std::size_t>(grid.node_count());
  std::vector<double> mass(nodes, 0.0);
  std::vector<Vec2> momentum(nodes, Vec2::Zero());
  std::vector<Stencil> stencils(particles.size());
  auto visit = [&](const Stencil& st, auto&& f) {
    for (int j = 0; j < st.y.count; ++j)
      for (int i = 0; i < st.x.count; ++i)
        f(static_cast<std::size_t>(grid.node_index(st.x.first + i, st.y.first + j)),
          st.x.weight[i] * st.y.weight[j]);
  };
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const Vec2& x = particles.position[p];
    compute_stencil(grid, ShapeFunction::cpgimp, x.x(), x.y(), particles.half_size[p].x(),
                    particles.half_size[p].y(), stencils[p]);
    visit(stencils[p], [&](std::size_t n, double s) {
      mass[n] += s * particles.mass[p];
      momentum[n] += s * particles.mass[p] * velocity[p];
    });
  }
  std::vector<Vec2> result(particles.size(), Vec2::Zero());
  for (std::size_t p = 0; p < particles.size(); ++p)
    visit(stencils[p], [&](std::size_t n, double s) {
      if (mass[n] == 0.0) return;  // a padded stencil node with zero weight
      const Vec2 v = momentum[n] / mass[n];
      result[p] += s * Vec2(grid.free_x()[n] * v.x(), grid.free_y()[n] * v.y());
    });
  return result;
}

std::vector<Vec2> one_step_without_forces(int order) {
  XpicModel s = make_setup();
  SolverSettings settings;
  settings.flip_fraction = 0.0;
  settings.xpic_order = order;
  settings.gravity = 0.0;
  settings.threads = 2;
  Solver solver(std::move(s.grid), std::move(s.particles),
                {std::make_shared<LinearElastic>(ElasticParameters{1.0e6, 0.2})}, settings);
  solver.step();
  return solver.particles().velocity;
}

TEST(Xpic, OneStepWithoutForcesIsTheFilterOneMinusOneMinusRoundTripToTheM) {
  const XpicModel s = make_setup();
  for (int order : {1, 2, 3, 5, 8}) {
    // Reference: W = (1 - A)^m V by m products, then V^1 = V - W.
    std::vector<Vec2> remainder = s.particles.velocity;
    for (int k = 0; k < order; ++k) {
      const std::vector<Vec2> smoothed = round_trip(s.grid, s.particles, remainder);
      for (std::size_t p = 0; p < remainder.size(); ++p) remainder[p] -= smoothed[p];
    }
    const std::vector<Vec2> velocity = one_step_without_forces(order);
    double largest_error = 0.0, largest_change = 0.0;
    for (std::size_t p = 0; p < velocity.size(); ++p) {
      const Vec2 expected = s.particles.velocity[p] - remainder[p];
      if (!(velocity[p].allFinite() && expected.allFinite())) largest_error = NAN;
      largest_error = std::max(largest_error, (velocity[p] - expected).norm());
      largest_change = std::max(largest_change, remainder[p].norm());
    }
    ASSERT_TRUE(std::isfinite(largest_error) && std::isfinite(largest_change));
    EXPECT_LT(largest_error, 1e-12) << "XPIC(" << order << ")";
    // The filter does remove something at every order (the reference is not the identity).
    EXPECT_GT(largest_change, 1e-3) << "XPIC(" << order << ")";
  }
}

TEST(Xpic, HigherOrdersKeepMoreOfTheVelocityAndConvergeToTheNullSpaceProjection) {
  // |V - V^1| falls with the order and its change between orders shrinks: the filtered part
  // converges to the null space of the round trip (what the grid cannot see).
  const XpicModel s = make_setup();
  auto removed = [&](int order) {
    const std::vector<Vec2> velocity = one_step_without_forces(order);
    double sum = 0.0;
    for (std::size_t p = 0; p < velocity.size(); ++p)
      sum += (velocity[p] - s.particles.velocity[p]).squaredNorm();
    return std::sqrt(sum);
  };
  const double pic = removed(1), xpic2 = removed(2), xpic4 = removed(4), xpic8 = removed(8);
  EXPECT_LT(xpic2, pic);
  EXPECT_LT(xpic4, xpic2);
  EXPECT_LT(xpic8, xpic4);
  EXPECT_LT(xpic4 - xpic8, xpic2 - xpic4);
}

TEST(Xpic, OrderOutOfRangeIsRejected) {
  SolverSettings settings;
  settings.xpic_order = 0;
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings.xpic_order = 9;
  EXPECT_THROW(settings.validate(), InvalidValue);
}

}  // namespace
}  // namespace pilempm::mpm
