// Quasi-static analysis (docs/quasi-static.md): the penalty contact at the corners of the
// particles' domains against the exact surface of rigid bodies, with Coulomb friction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"
#include "pilempm/mpm/quasi_static/rounded_surface.hpp"

namespace pilempm::mpm::quasi_static {
namespace {

// The point law alone: stick inside the cone, slip on it, the stiffness the derivative.
TEST(QuasiStaticContactLaw, StickSlipAndItsStiffnessMatchDifferences) {
  const Vec2 n(0.6, 0.8);
  const double kn = 1.0e6, kt = 5.0e5, mu = 0.4;
  // Stick: a small slip along the tangent.
  const Vec2 t(-0.8, 0.6);
  PointContact stick = penalty_contact(-1e-3, n, 1e-4 * t, Vec2::Zero(), kn, kt, mu);
  ASSERT_TRUE(stick.active);
  EXPECT_FALSE(stick.slip);
  EXPECT_NEAR(stick.normal_force, 1e3, 1e-9);
  EXPECT_NEAR(stick.tangential_force, -50.0, 1e-9);
  // Slip: a larger one; the force lies on the cone.
  PointContact slip = penalty_contact(-1e-3, n, 1e-2 * t, Vec2::Zero(), kn, kt, mu);
  EXPECT_TRUE(slip.slip);
  EXPECT_NEAR(std::abs(slip.tangential_force), mu * slip.normal_force, 1e-9);
  // Stiffness = -dF/dΔs, by central differences, in both states (the gap moves with n·Δs).
  for (const Vec2& base : {Vec2(1e-4 * t), Vec2(1e-2 * t)}) {
    const PointContact c = penalty_contact(-1e-3, n, base, Vec2::Zero(), kn, kt, mu);
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-8;
      Vec2 e = Vec2::Zero();
      e[k] = h;
      const PointContact plus =
          penalty_contact(-1e-3 + n.dot(e), n, base + e, Vec2::Zero(), kn, kt, mu);
      const PointContact minus =
          penalty_contact(-1e-3 - n.dot(e), n, base - e, Vec2::Zero(), kn, kt, mu);
      const Vec2 derivative = -(plus.force - minus.force) / (2.0 * h);
      EXPECT_NEAR((derivative - c.stiffness.col(k)).norm(), 0.0, 1e-6 * kn);
    }
  }
  // Out of contact: nothing.
  EXPECT_FALSE(penalty_contact(1e-6, n, Vec2::Zero(), Vec2::Zero(), kn, kt, mu).active);
}

// At a rounded vertex the normal turns with the point (∂n/∂x = κ t t^T, κ = 1/d_Q from the
// query): the stiffness holds the force's turning too, so that it is −dF/dx of the force at the
// queried gap and normal, in stick and in slip. Without the turning terms the error is about
// f_n κ, here half the tangential stiffness (it slowed the pile's Newton iterations to linear
// convergence where sand slid over the shoulder, docs/quasi-static.md).
TEST(QuasiStaticContactLaw, AtARoundedVertexTheStiffnessHoldsTheTurningOfTheNormal) {
  const RigidBody square =
      RigidBody::polygon({Vec2(0.0, 0.0), Vec2(1e-2, 0.0), Vec2(1e-2, 1e-2), Vec2(0.0, 1e-2)});
  const double rho = 2e-3;
  const detail::RoundedSurface surface(square, rho);
  const double kn = 1.0e6, kt = 1.0e5, mu = 0.05;
  // A point 0.5 mm deep in the arc at the corner (1 cm, 1 cm), 30° from the top face's normal.
  const Vec2 centre = Vec2(1e-2, 1e-2) - Vec2(rho, rho);
  const double angle = M_PI / 6.0;
  const Vec2 start = centre + (rho - 5e-4) * Vec2(std::sin(angle), std::cos(angle));
  const Vec2 previous = 20.0 * Vec2(-std::cos(angle), std::sin(angle));  // a stuck force
  const auto contact = [&](const Vec2& slip) {
    const SurfaceQuery q = surface.query(start + slip);
    return penalty_contact(q.distance, q.normal, slip, previous, kn, kt, mu, 0.0, 0.0, q.curvature);
  };
  ASSERT_NEAR(surface.query(start).curvature, 1.0 / (rho - 5e-4), 1e-6 / rho);
  // Stick (a small slip) and slip (a large one along the tangent).
  for (const Vec2& base :
       {Vec2(1e-5, 0.0), Vec2(2e-4 * std::cos(angle), -2e-4 * std::sin(angle))}) {
    const PointContact c = contact(base);
    ASSERT_TRUE(c.active);
    double error = 0.0, turning = 0.0;
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-9;
      Vec2 e = Vec2::Zero();
      e[k] = h;
      const Vec2 derivative = -(contact(base + e).force - contact(base - e).force) / (2.0 * h);
      error = std::max(error, (derivative - c.stiffness.col(k)).norm());
    }
    turning = c.normal_force / (rho - 5e-4);
    std::printf("%s: f_n %.1f N, f_n kappa %.3g N/m, error %.3g N/m\n", c.slip ? "slip" : "stick",
                c.normal_force, turning, error);
    EXPECT_GT(turning, 0.3 * kt);  // the turning terms matter here
    EXPECT_LT(error, 1e-5 * turning);
  }
}

// The penalty's length is the domain's size at creation: a cpGIMP domain squeezed to a sliver
// (the sand a pile pushes from the axis to its shaft, radial stretch r0 / r) keeps the stiffness
// per unit of its corner's boundary share, β M / d_p0, and with it the penetration under a given
// contact stress. With the current size the stiffness grew as 1 / squeeze.
TEST(QuasiStaticContactLaw, ASqueezedDomainKeepsThePenaltyOfItsSizeAtCreation) {
  const double beta = 2.0, modulus = 5.0e7, radius = 0.006;
  const Vec2 initial(7.0e-4, 7.0e-4);
  for (const double squeeze : {1.0, 0.1, 0.003}) {
    // A squeeze along x at constant area (F = diag(s, 1/s)): the cpGIMP stretch of the domain.
    const Mat2 deformation = Vec2(squeeze, 1.0 / squeeze).asDiagonal();
    const Vec2 half = stretched_half_size(initial, deformation);
    ASSERT_NEAR(half.x(), squeeze * initial.x(), 1e-12);
    const double kn = corner_normal_stiffness(beta, modulus, half, penalty_length(initial), radius);
    const double share = (half.x() + half.y()) * radius;
    // Per unit of the corner's share of the boundary, as for the square domain.
    EXPECT_NEAR(kn / share, beta * modulus / (2.0 * initial.x()), 1e-9 * kn / share) << squeeze;
    // A contact stress of 100 kPa on the share: the penetration σ d_p0 / (β M), whatever the
    // squeeze.
    const double sigma = 1.0e5;
    const double penetration = sigma * share / kn;
    EXPECT_NEAR(penetration, sigma * 2.0 * initial.x() / (beta * modulus), 1e-15) << squeeze;
  }
}

// The smoothed normal force: continuous with its slope at p = 0 and p = δ, the linear law shifted
// by δ/2 beyond, and the stiffness (stick and slip) its derivative inside the smoothing depth.
TEST(QuasiStaticContactLaw, TheSmoothedNormalForceIsContinuouslyDifferentiable) {
  const Vec2 n(0.6, 0.8), t(-0.8, 0.6);
  const double kn = 1.0e6, kt = 5.0e5, mu = 0.4, delta = 1e-3;
  const auto force = [&](double p, const Vec2& slip) {
    return penalty_contact(-p, n, slip, Vec2::Zero(), kn, kt, mu, 0.0, delta);
  };
  EXPECT_NEAR(force(0.5 * delta, Vec2::Zero()).normal_force, kn * 0.125 * delta, 1e-12 * kn);
  EXPECT_NEAR(force(3.0 * delta, Vec2::Zero()).normal_force, kn * 2.5 * delta, 1e-12 * kn);
  for (const double at : {1e-9, delta}) {  // value and slope meet at both ends of the ramp
    const double e = 1e-9 * delta;
    EXPECT_NEAR(force(at + e, Vec2::Zero()).normal_force, force(at - e, Vec2::Zero()).normal_force,
                1e-6 * kn * delta);
    const double below =
        (force(at, Vec2::Zero()).normal_force - force(at - e, Vec2::Zero()).normal_force) / e;
    const double above =
        (force(at + e, Vec2::Zero()).normal_force - force(at, Vec2::Zero()).normal_force) / e;
    EXPECT_NEAR(below, above, 1e-5 * kn);
  }
  // The normal stiffness vanishes where the point enters contact (the stick stiffness k_t t t^T
  // stays).
  EXPECT_NEAR(n.dot(force(1e-12, Vec2::Zero()).stiffness * n), 0.0, 1e-8 * kn);
  // Inside the ramp, in stick (small slip) and slip (large): -dF/dΔs by central differences.
  const double p = 0.4 * delta;
  for (const Vec2& base : {Vec2(1e-6 * t), Vec2(1e-2 * t)}) {
    const PointContact c = force(p, base);
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-10;
      Vec2 e = Vec2::Zero();
      e[k] = h;
      const Vec2 derivative =
          -(force(p - n.dot(e), base + e).force - force(p + n.dot(e), base - e).force) / (2.0 * h);
      EXPECT_NEAR((derivative - c.stiffness.col(k)).norm(), 0.0, 1e-5 * kn);
    }
  }
}

// Verification 5: an elastic block on a rough rigid floor (μ = 0.5), first loaded by its weight,
// then pushed sideways by a smooth rigid plate. Below μ N the floor sticks and takes the push;
// once the block slides the floor's tangential force is μ times its normal force.
TEST(QuasiStaticContact, BlockOnARoughFloorSticksThenSlipsAtMuTimesTheNormalForce) {
  const double h = 0.025, mu = 0.5;
  const double gap_x = 0.1 - 1e-5;  // the plate's face, clear of the block's Poisson bulge
  Grid grid(GridAxis::uniform(0.0, 0.5, 20), GridAxis::uniform(-0.1, 0.2, 12));
  Particles particles;
  RectangleFill fill;
  fill.x_min = 0.1;
  fill.x_max = 0.3;
  fill.y_min = 0.0;
  fill.y_max = 0.1;
  fill.density = 2000.0;
  fill_rectangle(particles, grid, Geometry::plane_strain, fill);
  Settings settings;
  settings.force_tolerance = 1e-8;
  auto model = std::make_shared<LinearElastic>(ElasticParameters{10.0e6, 0.3});
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, settings);
  RigidBody floor = RigidBody::polygon({{-1.0, -1.0}, {1.0, -1.0}, {1.0, 0.0}, {-1.0, 0.0}});
  floor.set_friction(mu);
  const int floor_index = solver.add_rigid_body(std::move(floor));
  const int plate_index = solver.add_rigid_body(
      RigidBody::polygon({{-0.9, 0.2 * h}, {gap_x, 0.2 * h}, {gap_x, 0.5}, {-0.9, 0.5}}));
  const double weight = 2000.0 * 9.81 * 0.2 * 0.1;  // per unit thickness [N/m]

  LoadStep gravity;
  gravity.gravity_multiplier = 1.0;
  gravity.body_displacement = {Vec2::Zero(), Vec2::Zero()};
  LoadStepResult r = solver.solve_step(gravity);
  ASSERT_TRUE(r.converged) << r.message;
  const BodyForce& on_floor = solver.body_force(floor_index);
  EXPECT_NEAR(-on_floor.total.y(), weight, 1e-6 * weight);
  EXPECT_NEAR(on_floor.total.x(), 0.0, 1e-6 * weight);
  std::printf("weight %.3f N/m, floor takes %.3f; penetration %.2e m = %.2e of a cell\n", weight,
              -on_floor.total.y(), solver.max_penetration(), solver.max_penetration() / h);
  EXPECT_LT(solver.max_penetration(), 0.01 * h);

  // Stick: a small push.
  LoadStep push;
  push.gravity_multiplier = 1.0;
  push.body_displacement = {Vec2::Zero(), Vec2(1e-5 + 1e-7, 0.0)};
  r = solver.solve_step(push);
  ASSERT_TRUE(r.converged) << r.message;
  {
    const Vec2 f_floor = solver.body_force(floor_index).total;
    const Vec2 f_plate = solver.body_force(plate_index).total;
    std::printf("stick: plate %.3f N/m, floor tangential %.3f, μ N %.3f\n", f_plate.x(),
                f_floor.x(), -mu * f_floor.y());
    // The plate pushes (+x), the block pushes back on it (−x); the floor is dragged along (+x).
    EXPECT_LT(f_plate.x(), -0.02 * weight);
    EXPECT_GT(f_plate.x(), -0.9 * mu * weight);
    EXPECT_NEAR(f_floor.x(), -f_plate.x(), 1e-6 * weight);
  }
  // Slip: push on by 2 mm in steps.
  for (int step = 0; step < 4; ++step) {
    push.body_displacement = {Vec2::Zero(), Vec2(5e-4, 0.0)};
    r = solver.solve_step(push);
    ASSERT_TRUE(r.converged) << r.message;
    const Vec2 f_floor = solver.body_force(floor_index).total;
    const Vec2 f_plate = solver.body_force(plate_index).total;
    std::printf("slip: plate %.4f N/m, floor tangential %.4f, μ N %.4f, %d iterations\n",
                f_plate.x(), f_floor.x(), -mu * f_floor.y(), r.iterations);
    EXPECT_NEAR(f_floor.x(), -mu * f_floor.y(), 1e-6 * weight);  // f_floor.y() < 0
    EXPECT_NEAR(f_plate.x(), -mu * weight, 1e-6 * weight);
  }
  EXPECT_NEAR(solver.rigid_body(plate_index).displacement().x(), 2e-3 + 1e-5 + 1e-7, 1e-12);
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static

namespace pilempm::mpm::quasi_static {
namespace {

// Verification 3: a rigid flat circular punch (radius a) pressed by δ into an elastic layer
// (axisymmetric; radius 8 a, thickness 8 a, rollers at the side, fixed base), smooth and rough.
// Sneddon (1946) for a half-space: F = 2 a E δ / (1 − ν²) (full circle; per radian F / 2π).
// How the layer is accounted for: by a bound, not a correction. The layer on a rigid base with a
// rolling side is stiffer than the half-space, and so is the displacement discretisation: the
// half-space value is a lower bound (the penalty's own compliance, about d_p / (4 a) ≈ 6 % of δ
// here, works the other way and is smaller than the layer's stiffening). The upper limit 1.25 is a
// stated tolerance for the layer of 8 a and cells of a/4, not a derived value. Rough and smooth
// punches differ by a few per cent at ν = 0.3 (Spence 1968): the rough one is the stiffer, by
// less than 5 %.
double punch_force(double friction, double& penetration_fraction) {
  const double a = 0.1, e = 10.0e6, nu = 0.3, h = a / 4.0;
  const int cells = 32;
  Grid grid(GridAxis::uniform(0.0, cells * h, cells),
            GridAxis::uniform(0.0, (cells + 2) * h, cells + 2));
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
  Particles particles;
  RectangleFill fill;
  fill.x_max = cells * h;
  fill.y_max = cells * h;
  fill.density = 2000.0;
  fill_rectangle(particles, grid, Geometry::axisymmetric, fill);
  Settings settings;
  settings.geometry = Geometry::axisymmetric;
  settings.gravity = 0.0;
  auto model = std::make_shared<LinearElastic>(ElasticParameters{e, nu});
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, settings);
  RigidBody punch = RigidBody::pile(a, cells * h, kPi);
  punch.set_friction(friction);
  solver.add_rigid_body(std::move(punch));
  const double settlement = 1e-4 * a;
  LoadStep load;
  load.gravity_multiplier = 0.0;
  load.body_displacement = {Vec2(0.0, -settlement)};
  const LoadStepResult r = solver.solve_step(load);
  EXPECT_TRUE(r.converged) << r.message;
  penetration_fraction = solver.max_penetration() / settlement;
  const double force = 2.0 * kPi * solver.body_force(0).total.y();
  const double sneddon = 2.0 * a * e * settlement / (1.0 - nu * nu);
  std::printf(
      "punch μ = %.1f: F = %.4f N, Sneddon %.4f N, ratio %.4f, %d iterations, largest "
      "penetration %.3f of δ\n",
      friction, force, sneddon, force / sneddon, r.iterations, penetration_fraction);
  return force / sneddon;
}

TEST(QuasiStaticContact, FlatPunchOnAnElasticLayerLiesBetweenSneddonAndTheLayerBound) {
  double smooth_penetration = 0.0, rough_penetration = 0.0;
  const double smooth = punch_force(0.0, smooth_penetration);
  const double rough = punch_force(10.0, rough_penetration);
  EXPECT_GT(smooth, 1.0);
  EXPECT_LT(smooth, 1.25);
  EXPECT_GT(rough, 1.0);
  EXPECT_LT(rough, 1.25);
  EXPECT_GE(rough, smooth * 0.999);
  EXPECT_LT(rough / smooth, 1.05);
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static
