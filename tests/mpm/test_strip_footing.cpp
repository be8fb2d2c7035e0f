// Strip footing on undrained (φ = 0) Mohr-Coulomb soil: a rigid, smooth footing of width B pushed
// into a weightless Tresca layer reaches Prandtl's bearing pressure q_u = (2 + π) c (Prandtl 1920;
// the exact limit load of a rigid-perfectly plastic half-space under a smooth strip). Half model in
// plane strain: the symmetry plane x = 0 is a roller, the footing a rigid polygon from x = -h to
// B/2 moved down at a constant slow speed; the pressure is the contact force over B/2.
//
// Without the volumetric-locking remedy the isochoric plastic flow (ψ = 0) locks the mesh and the
// pressure overshoots the limit; with it the pressure levels off at the limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "pilempm/constitutive/mohr_coulomb.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kCohesion = 10.0e3;  // c [Pa]
constexpr double kHalfWidth = 0.5;    // B/2 [m]
constexpr double kDepth = 1.0;        // soil layer [m]
constexpr double kSoilWidth = 1.5;    // half model [m]
constexpr double kRampTime = 1.0;     // the pressure rises linearly over this time [s]
constexpr double kHoldTime = 1.0;     // then stays [s]

// Settlement of the loaded strip's surface particles [m]: at the end of the ramp to the target
// pressure and at the end of the hold that follows.
struct FootingSettlement {
  double after_ramp = 0.0;
  double after_hold = 0.0;
};

FootingSettlement load_strip(double h, double pressure, bool smoothing) {
  Grid grid(
      GridAxis::uniform(0.0, kSoilWidth, static_cast<int>(std::lround(kSoilWidth / h))),
      GridAxis::uniform(0.0, kDepth + 4.0 * h, static_cast<int>(std::lround(kDepth / h)) + 4));
  grid.set_boundary(Side::left, BoundaryCondition::roller);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);

  Particles particles;
  RectangleFill fill;
  fill.x_max = kSoilWidth;
  fill.y_max = kDepth;
  fill.density = 2000.0;
  fill_rectangle(particles, grid, Geometry::plane_strain, fill);
  // The strip load: on the top row of particles under the footing, each its share of the width.
  std::vector<std::size_t> loaded;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const Vec2& x = particles.position[p];
    if (x.y() > kDepth - 0.5 * h && x.x() < kHalfWidth) loaded.push_back(p);
  }
  const double share = kHalfWidth / static_cast<double>(loaded.size());

  MohrCoulombParameters soil;
  soil.young_modulus = 10.0e6;  // E / c = 1000
  soil.poisson_ratio = 0.3;
  soil.cohesion = kCohesion;
  soil.friction_angle_deg = 0.0;
  soil.dilatancy_angle_deg = 0.0;
  SolverSettings settings;
  settings.gravity = 0.0;
  settings.local_damping = 0.7;  // quasi-static
  settings.volumetric_smoothing = smoothing;
  settings.threads = 2;
  Solver solver(std::move(grid), std::move(particles), {std::make_shared<MohrCoulomb>(soil)},
                settings);
  auto settlement = [&] {
    double sum = 0.0;
    for (std::size_t p : loaded) sum += kDepth - solver.particles().position[p].y();
    return sum / static_cast<double>(loaded.size());
  };
  FootingSettlement result;
  const int ramp_steps = 50;
  for (int k = 1; k <= ramp_steps; ++k) {
    const double q = pressure * k / ramp_steps;
    for (std::size_t p : loaded) solver.particles().external_force[p] = Vec2(0.0, -q * share);
    solver.run_until(kRampTime * k / ramp_steps);
  }
  result.after_ramp = settlement();
  solver.run_until(kRampTime + kHoldTime);
  result.after_hold = settlement();
  return result;
}

// A uniform pressure on a strip of weightless Tresca soil: below Prandtl's (2 + π) c the soil
// carries it (the settlement stops), above it a mechanism forms and the settlement runs on.
TEST(StripFooting, FlexibleStripCollapsesAtPrandtlsLoad) {
  const double h = 0.05;
  const double prandtl = (2.0 + std::numbers::pi) * kCohesion;
  for (const double factor : {0.9, 0.95, 1.05, 1.1}) {
    const FootingSettlement s = load_strip(h, factor * prandtl, true);
    std::printf("q = %.2f q_u: settlement %.5f m after the ramp, %.5f m after the hold\n", factor,
                s.after_ramp, s.after_hold);
  }
}

}  // namespace
}  // namespace pilempm::mpm
