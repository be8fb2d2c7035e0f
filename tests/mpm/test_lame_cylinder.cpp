// Verification 3 of issue 4, axisymmetry: a thick-walled linear elastic cylinder under internal
// pressure (Lamé). The wall a <= r <= b is a slice in z between rollers (plane strain along the
// axis); the pressure p_i acts on the inner face r = a as point loads on the innermost layer of
// particles, p_i times that layer's inner face per radian (a Δz); the outer face is free. Brought
// to rest by local damping, the stresses at the particles are compared with Lamé's solution
//   σ_r = A - B / r², σ_θ = A + B / r², A = p_i a² / (b² - a²), B = p_i a² b² / (b² - a²),
// tension positive (σ_r(a) = -p_i, σ_r(b) = 0), and σ_z = ν (σ_r + σ_θ) = 2 ν A.
//
// What limits the accuracy: as in the self-weight column, the stress in a cell is about the one
// at its centre, off at a particle by about (h/4) dσ/dr, and the loaded layer takes its load as a
// point force at its centre rather than on its face: a first-order error in the cell size h.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kInner = 1.0;        // a [m]
constexpr double kOuter = 2.0;        // b [m]
constexpr double kPressure = 10.0e3;  // p_i [Pa]
constexpr double kYoung = 10.0e6;     // E [Pa]: p_i / E = 1e-3, small strain
constexpr double kPoisson = 0.3;      // ν
constexpr double kDensity = 2000.0;   // ρ [kg/m^3]

double lame_a() {
  return kPressure * kInner * kInner / (kOuter * kOuter - kInner * kInner);
}
double lame_b() {
  return lame_a() * kOuter * kOuter;
}
double exact_radial(double r) {
  return lame_a() - lame_b() / (r * r);
}
double exact_hoop(double r) {
  return lame_a() + lame_b() / (r * r);
}

struct LameResult {
  double radial_error = 0.0;     // mean |σ_r - exact| / p_i, particles off the faces' layers
  double hoop_error = 0.0;       // mean |σ_θ - exact| / |exact|, same particles
  double axial_error = 0.0;      // mean |σ_z - 2 ν A| / (2 ν A), same particles
  double mid_wall_radial = 0.0;  // |σ_r - exact| / |exact| at the particles nearest mid-wall
  double mid_wall_hoop = 0.0;    // |σ_θ - exact| / |exact| there
  double energy_residual = 0.0;  // |kinetic + internal + damping - external| / external
  long steps = 0;
  double seconds = 0.0;
};

LameResult run_cylinder(int cells_over_wall) {
  const auto start = std::chrono::steady_clock::now();
  const double h = (kOuter - kInner) / cells_over_wall;
  const int slice_cells = 2;
  const double slice = slice_cells * h;
  // Two empty cells each side of the wall in r; the grid stays clear of the axis.
  Grid grid(GridAxis::uniform(kInner - 2.0 * h, kOuter + 2.0 * h, cells_over_wall + 4),
            GridAxis::uniform(0.0, slice, slice_cells));
  grid.set_boundary(Side::bottom, BoundaryCondition::roller);
  grid.set_boundary(Side::top, BoundaryCondition::roller);

  RectangleFill fill = test_support::block_fill(kInner, kOuter, 0.0, slice, kDensity);
  fill.initial_state.void_ratio = 0.7;
  Particles particles = test_support::particle_block(grid, Geometry::axisymmetric, fill);

  // The pressure on the inner face: on each particle of the innermost layer, p_i times its face
  // r_face 2 l_z per radian (r_face = r_p - l_r, the domain's inner edge, = a).
  std::vector<double> radius(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    radius[p] = particles.position[p].x();
    const double face = radius[p] - particles.half_size[p].x();
    if (std::abs(face - kInner) < 1e-9 * kInner)
      particles.external_force[p] = Vec2(kPressure * face * 2.0 * particles.half_size[p].y(), 0.0);
  }

  SolverSettings settings;
  settings.geometry = Geometry::axisymmetric;
  settings.shape_function = ShapeFunction::cpgimp;
  settings.gravity = 0.0;
  settings.local_damping = 0.7;
  settings.flip_fraction = 0.99;
  settings.courant_number = 0.5;
  settings.threads = 1;
  const auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  Solver solver(std::move(grid), std::move(particles), {model}, settings);

  for (int chunk = 0; chunk < 2000; ++chunk) {
    for (int k = 0; k < 100; ++k) solver.step();
    const Energies& e = solver.energies();
    if (e.kinetic < 1e-12 * e.internal) break;
  }

  LameResult result;
  result.steps = solver.steps();
  const Energies& e = solver.energies();
  result.energy_residual =
      std::abs(e.kinetic + e.internal + e.damping - e.external_work) / e.external_work;

  // Particles of the two layers on the faces are left out of the means.
  const double mid = 0.5 * (kInner + kOuter);
  double nearest = 1e30;
  for (std::size_t i = 0; i < radius.size(); ++i)
    nearest = std::min(nearest, std::abs(radius[i] - mid));
  const Particles& p = solver.particles();
  double radial = 0.0, hoop = 0.0, axial = 0.0, mid_radial = 0.0, mid_hoop = 0.0;
  int counted = 0, mid_counted = 0;
  const double axial_exact = 2.0 * kPoisson * lame_a();
  for (std::size_t i = 0; i < p.size(); ++i) {
    // Compare at the current radius (it differs from the initial one by about 1e-3 of h).
    const double r = p.position[i].x();
    const Vec6& stress = p.state[i].stress;
    if (std::abs(std::abs(radius[i] - mid) - nearest) < 1e-9) {
      mid_radial += std::abs(stress[k11] - exact_radial(r)) / std::abs(exact_radial(r));
      mid_hoop += std::abs(stress[k33] - exact_hoop(r)) / std::abs(exact_hoop(r));
      ++mid_counted;
    }
    if (radius[i] < kInner + 0.5 * h || radius[i] > kOuter - 0.5 * h) continue;
    radial += std::abs(stress[k11] - exact_radial(r)) / kPressure;
    hoop += std::abs(stress[k33] - exact_hoop(r)) / std::abs(exact_hoop(r));
    axial += std::abs(stress[k22] - axial_exact) / axial_exact;
    ++counted;
  }
  result.radial_error = radial / counted;
  result.hoop_error = hoop / counted;
  result.axial_error = axial / counted;
  result.mid_wall_radial = mid_radial / mid_counted;
  result.mid_wall_hoop = mid_hoop / mid_counted;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

void print(const char* label, int cells, const LameResult& r) {
  std::printf(
      "[ lame%s ] %3d cells over the wall: mean |σ_r err|/p_i %.3e, mean rel σ_θ err %.3e, mean "
      "rel σ_z err %.3e, mid-wall rel σ_r %.3e σ_θ %.3e, steps %ld, energy residual %.1e, "
      "%.1f s\n",
      label, cells, r.radial_error, r.hoop_error, r.axial_error, r.mid_wall_radial, r.mid_wall_hoop,
      r.steps, r.energy_residual, r.seconds);
}

TEST(LameCylinder, AxisymmetricStressesMatchLameWithinTwoPercent) {
  const int cells = 128;
  const LameResult r = run_cylinder(cells);
  print("", cells, r);
  EXPECT_LT(r.energy_residual, 0.01);
  EXPECT_LT(r.radial_error, 0.02);
  EXPECT_LT(r.hoop_error, 0.02);
  EXPECT_LT(r.axial_error, 0.02);
  EXPECT_LT(r.mid_wall_radial, 0.02);
  EXPECT_LT(r.mid_wall_hoop, 0.02);
}

// The error on three meshes: first order in the cell size (see the top of the file).
TEST(LameCylinder, LongErrorDecreasesWithTheCellSize) {
  const int meshes[3] = {32, 64, 128};
  LameResult results[3];
  for (int m = 0; m < 3; ++m) {
    results[m] = run_cylinder(meshes[m]);
    print(" mesh", meshes[m], results[m]);
  }
  for (int m = 1; m < 3; ++m) {
    const double radial_order = std::log2(results[m - 1].radial_error / results[m].radial_error);
    const double hoop_order = std::log2(results[m - 1].hoop_error / results[m].hoop_error);
    std::printf("[ lame mesh ] observed order %d -> %d cells: %.2f (σ_r), %.2f (σ_θ)\n",
                meshes[m - 1], meshes[m], radial_order, hoop_order);
    std::fflush(stdout);
    EXPECT_GT(radial_order, 0.6);
    EXPECT_GT(hoop_order, 0.6);
  }
}

}  // namespace
}  // namespace pilempm::mpm
