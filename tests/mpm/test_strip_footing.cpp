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

constexpr double kCohesion = 10.0e3;    // c [Pa]
constexpr double kHalfWidth = 0.5;      // B/2 [m]
constexpr double kDepth = 1.0;          // soil layer [m]
constexpr double kSoilWidth = 1.5;      // half model [m]
constexpr double kFootingSpeed = 0.05;  // [m/s]
constexpr double kSettlement = 0.025;   // final settlement [m] (half a cell at h = 0.05 m)

struct FootingCurve {
  std::vector<double> settlement;  // [m]
  std::vector<double> pressure;    // q / c [-]
};

FootingCurve push_footing(double h, bool smoothing) {
  const double top = kDepth;
  Grid grid(
      GridAxis::uniform(0.0, kSoilWidth, static_cast<int>(std::lround(kSoilWidth / h))),
      GridAxis::uniform(0.0, kDepth + 4.0 * h, static_cast<int>(std::lround(kDepth / h)) + 4));
  grid.set_boundary(Side::left, BoundaryCondition::roller);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);

  Particles particles;
  RectangleFill fill;
  fill.x_max = kSoilWidth;
  fill.y_max = top;
  fill.density = 2000.0;
  fill_rectangle(particles, grid, Geometry::plane_strain, fill);

  MohrCoulombParameters soil;
  soil.young_modulus = 10.0e6;  // E / c = 1000
  soil.poisson_ratio = 0.3;
  soil.cohesion = kCohesion;
  soil.friction_angle_deg = 0.0;
  soil.dilatancy_angle_deg = 0.0;

  SolverSettings settings;
  settings.gravity = 0.0;
  settings.local_damping = 0.1;
  settings.volumetric_smoothing = smoothing;
  settings.threads = 2;
  Solver solver(std::move(grid), std::move(particles), {std::make_shared<MohrCoulomb>(soil)},
                settings);
  RigidBody footing =
      RigidBody::polygon({{-h, top}, {kHalfWidth, top}, {kHalfWidth, top + 1.0}, {-h, top + 1.0}});
  footing.set_velocity(Vec2(0.0, -kFootingSpeed));
  const int body = solver.add_rigid_body(std::move(footing));

  FootingCurve curve;
  const int samples = 15;
  double force_sum = 0.0;
  long force_steps = 0;
  for (int k = 1; k <= samples; ++k) {
    const double end = kSettlement / kFootingSpeed * k / samples;
    while (solver.time() < end - 1e-12) {
      solver.run_until(std::min(end, solver.time() + solver.next_time_step()));
      force_sum += solver.rigid_body_force(body).total.y();
      ++force_steps;
    }
    // The mean contact force over the sample interval (a single step's force is noisy).
    curve.settlement.push_back(-solver.rigid_body(body).displacement().y());
    curve.pressure.push_back(force_sum / static_cast<double>(force_steps) / kHalfWidth / kCohesion);
    force_sum = 0.0;
    force_steps = 0;
  }
  return curve;
}

// The mean q/c over the plateau, s in [0.2 h, 0.5 h]. At s = h/2 the contact (half a cell reach)
// takes in the next node row below the footing, and from there to s = h the pressure sits about
// 20 % higher (measured 6.2 c at h = 0.05 m); the cycle repeats every cell. That is a limit of the
// nodal rigid-body contact, documented in docs/verification.md; the plateau before it measures
// the soil's collapse load.
double plateau(const FootingCurve& curve, double h) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < curve.settlement.size(); ++k) {
    std::printf("  settlement %.4f m, q/c %.3f\n", curve.settlement[k], curve.pressure[k]);
    if (curve.settlement[k] >= 0.2 * h - 1e-9 && curve.settlement[k] <= 0.5 * h + 1e-9) {
      sum += curve.pressure[k];
      ++count;
    }
  }
  return sum / count;
}

TEST(StripFooting, SmoothedPlateauIsPrandtlsLoadAndLockingRaisesIt) {
  const double h = 0.05;
  const double prandtl = 2.0 + std::numbers::pi;
  const double smoothed = plateau(push_footing(h, true), h);
  const double locked = plateau(push_footing(h, false), h);
  std::printf("strip footing: q/c = %.3f smoothed, %.3f without smoothing; Prandtl %.3f\n",
              smoothed, locked, prandtl);
  // Measured: 5.146 (+0.1 %) smoothed, 5.436 (+5.7 %) without.
  EXPECT_NEAR(smoothed / prandtl, 1.0, 0.05);
  EXPECT_GT(locked, 1.02 * smoothed);
}

}  // namespace
}  // namespace pilempm::mpm
