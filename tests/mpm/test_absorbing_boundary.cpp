// Absorbing (viscous) boundaries: an elastic bar, one particle row between rollers, starts with a
// velocity pulse near its free left end. The pulse splits into two waves; both end up at the right
// end (one directly, one after reflecting at the free end). With dashpots ρ c_p on the right side
// the waves leave the bar: after 3 L/c the energy left in it is a small fraction of the start,
// while with a fixed right end it is all still there. The energy account closes with the absorbed
// energy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kLength = 2.0;      // L [m]
constexpr double kDensity = 1000.0;  // ρ [kg/m^3]
constexpr double kYoung = 10.0e6;    // E [Pa], ν = 0: c = sqrt(E / ρ) = 100 m/s

struct BarEnergies {
  double initial = 0.0;    // kinetic energy of the pulse [J/m]
  double remaining = 0.0;  // kinetic + internal after 3 L/c [J/m]
  double absorbed = 0.0;   // by the dashpots [J/m]
};

BarEnergies run_pulse(bool absorbing, Geometry geometry) {
  const int cells = 80;
  const double h = kLength / cells;
  const double x0 = geometry == Geometry::axisymmetric ? 10.0 : 0.0;  // far from the axis
  Grid grid(GridAxis::uniform(x0, x0 + kLength, cells), GridAxis::uniform(0.0, h, 1));
  grid.set_boundary(Side::bottom, BoundaryCondition::roller);
  grid.set_boundary(Side::top, BoundaryCondition::roller);
  if (!absorbing) grid.set_boundary(Side::right, BoundaryCondition::fixed);

  RectangleFill fill = test_support::block_fill(x0, x0 + kLength, 0.0, h, kDensity);
  fill.particles_per_cell_x = 2;
  fill.particles_per_cell_y = 1;
  Particles particles = test_support::particle_block(grid, geometry, fill);
  // A smooth pulse (half sine, 0.4 m long) 0.2 m from the free end.
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double s = particles.position[p].x() - x0 - 0.2;
    if (s > 0.0 && s < 0.4)
      particles.velocity[p] = Vec2(0.1 * std::sin(std::numbers::pi * s / 0.4), 0.0);
  }

  SolverSettings settings;
  settings.geometry = geometry;
  settings.gravity = 0.0;
  settings.flip_fraction = 1.0;
  settings.threads = 1;
  const double wave_speed = std::sqrt(kYoung / kDensity);
  if (absorbing)
    settings.absorbing_boundaries.push_back(
        AbsorbingBoundary{Side::right, kDensity, wave_speed, wave_speed / std::sqrt(2.0)});
  Solver solver(std::move(grid), std::move(particles),
                {std::make_shared<LinearElastic>(ElasticParameters{kYoung, 0.0})}, settings);
  BarEnergies result;
  result.initial = solver.energies().kinetic;
  solver.run_until(3.0 * kLength / wave_speed);
  const Energies& e = solver.energies();
  result.remaining = e.kinetic + e.internal;
  result.absorbed = e.absorbed;
  return result;
}

TEST(AbsorbingBoundary, PlaneWaveLeavesTheBar) {
  const BarEnergies fixed = run_pulse(false, Geometry::plane_strain);
  const BarEnergies absorbing = run_pulse(true, Geometry::plane_strain);
  std::printf("left in the bar: fixed end %.4f, absorbing %.4f; balance %.4f\n",
              fixed.remaining / fixed.initial, absorbing.remaining / absorbing.initial,
              (absorbing.remaining + absorbing.absorbed) / absorbing.initial);
  // Measured: 0.24 % left with dashpots; 100.9 % with a fixed end (the kinetic energy belongs to
  // mid-step, see test_bar_vibration.cpp).
  EXPECT_NEAR(fixed.remaining / fixed.initial, 1.0, 0.02);
  EXPECT_EQ(fixed.absorbed, 0.0);
  EXPECT_LT(absorbing.remaining / absorbing.initial, 0.01);
  // The energy account closes: what is not left was absorbed.
  EXPECT_NEAR((absorbing.remaining + absorbing.absorbed) / absorbing.initial, 1.0, 0.02);
}

TEST(AbsorbingBoundary, AxisymmetricDashpotsScaleWithTheRadius) {
  // Far from the axis a radial bar behaves nearly as a plane one: the dashpot per radian carries
  // the factor r, like the bar's mass, so the same fraction leaves.
  const BarEnergies absorbing = run_pulse(true, Geometry::axisymmetric);
  std::printf("axisymmetric: left %.4f, balance %.4f\n", absorbing.remaining / absorbing.initial,
              (absorbing.remaining + absorbing.absorbed) / absorbing.initial);
  EXPECT_LT(absorbing.remaining / absorbing.initial, 0.02);  // measured 0.64 %
  EXPECT_NEAR((absorbing.remaining + absorbing.absorbed) / absorbing.initial, 1.0, 0.03);
}

TEST(AbsorbingBoundary, BadDashpotsAreRejected) {
  SolverSettings settings;
  settings.absorbing_boundaries.push_back(AbsorbingBoundary{Side::right, 0.0, 100.0, 50.0});
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings.absorbing_boundaries[0].density = 1000.0;
  settings.absorbing_boundaries.push_back(AbsorbingBoundary{Side::right, 1000.0, 100.0, 50.0});
  EXPECT_THROW(settings.validate(), InvalidValue);  // two on one side
  settings.absorbing_boundaries.pop_back();
  settings.absorbing_boundaries[0].p_wave_speed = -1.0;
  EXPECT_THROW(settings.validate(), InvalidValue);
}

}  // namespace
}  // namespace pilempm::mpm
