// A column of linear elastic soil under its own weight, brought to rest by local damping: with
// rollers on the sides (and the axis) and a fixed base the vertical stress at a material point is
// the weight of the material above it, σ_yy = -ρ g (H - Y) (Y its initial height), in plane strain
// and in axisymmetry alike, whatever ν. Checked on three meshes for accuracy and convergence.
//
// What limits the accuracy: with particle domains that fill their cells (2 x 2 particles per
// cell), GIMP reduces to linear shape functions in this 1D state, so the stress is constant in a
// cell, exact at its centre (nodally exact displacements) and off by ρ g h/4 at the particles, a
// first-order error of about (h/4) / depth relative to the local stress.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {
namespace {

constexpr double kHeight = 1.0;      // H [m]
constexpr double kDensity = 2000.0;  // ρ [kg/m^3]
constexpr double kGravity = 9.81;

struct ColumnResult {
  double mean_error = 0.0;  // mean |σ_yy - exact| / (ρ g (H - Y)) over points deeper than 0.2 H
  double rms_error = 0.0;   // RMS of (σ_yy - exact) / (ρ g H) over all points
  long steps = 0;
  double energy_residual = 0.0;      // |kinetic + internal + damping - external| / external
  double lateral_ratio_error = 0.0;  // max |σ_xx/σ_yy - K0|, |σ_33/σ_yy - K0|, K0 = ν/(1-ν)
};

// Runs until the kinetic energy is negligible, or `fixed_steps` steps when given.
ColumnResult run_column(Geometry geometry, int cells_over_height, ShapeFunction shape,
                        double gravity_multiplier = 1.0,
                        std::vector<double>* vertical_stress = nullptr, long fixed_steps = 0) {
  const double h = kHeight / cells_over_height;
  const int columns = 2;
  // The column fills x in [x0, x0 + 2h]; in axisymmetry it starts on the axis.
  Grid grid(GridAxis::uniform(0.0, columns * h, columns),
            GridAxis::uniform(0.0, kHeight + 2.0 * h, cells_over_height + 2));
  test_support::set_walls_and_fixed_base(grid);

  RectangleFill fill = test_support::block_fill(0.0, columns * h, 0.0, kHeight, kDensity);
  fill.initial_state.void_ratio = 0.7;
  Particles particles = test_support::particle_block(grid, geometry, fill);
  std::vector<double> initial_height(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) initial_height[p] = particles.position[p].y();

  const double poisson_ratio = 0.3;
  // The stiffness scales with the gravity multiplier, so that the strains do not change.
  const auto model = std::make_shared<LinearElastic>(
      ElasticParameters{10.0e6 * gravity_multiplier, poisson_ratio});
  SolverSettings settings;
  settings.geometry = geometry;
  settings.shape_function = shape;
  settings.gravity = kGravity;
  settings.gravity_multiplier = gravity_multiplier;
  settings.local_damping = 0.7;
  // A little PIC: with pure FLIP, particle velocity modes the grid cannot see never decay, and the
  // kinetic energy stalls at a small constant instead of going to zero.
  settings.flip_fraction = 0.99;
  settings.courant_number = 0.5;
  settings.threads = 1;
  Solver solver(std::move(grid), std::move(particles), {model}, settings);

  ColumnResult result;
  for (long k = 0; k < fixed_steps; ++k) solver.step();
  // Run until the kinetic energy is negligible against the strain energy.
  for (int chunk = 0; chunk < 1000 && fixed_steps == 0; ++chunk) {
    for (int k = 0; k < 100; ++k) solver.step();
    const Energies& e = solver.energies();
    if (e.kinetic < 1e-12 * e.internal) break;
  }
  result.steps = solver.steps();
  const Energies& e = solver.energies();
  result.energy_residual =
      std::abs(e.kinetic + e.internal + e.damping - e.external_work) / e.external_work;

  const Particles& p = solver.particles();
  if (vertical_stress)
    for (const MaterialState& state : p.state) vertical_stress->push_back(state.stress[k22]);
  double sum = 0.0, squares = 0.0;
  int counted = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double depth = kHeight - initial_height[i];
    const double exact = -kDensity * kGravity * gravity_multiplier * depth;
    const Vec6& stress = p.state[i].stress;
    const double error = stress[k22] - exact;
    // Oedometric state: σ_xx = σ_33 (σ_zz or σ_θθ) = ν/(1-ν) σ_yy, whatever the mesh.
    const double k0 = poisson_ratio / (1.0 - poisson_ratio);
    result.lateral_ratio_error =
        std::max({result.lateral_ratio_error, std::abs(stress[k11] / stress[k22] - k0),
                  std::abs(stress[k33] / stress[k22] - k0)});
    squares += std::pow(error / (kDensity * kGravity * gravity_multiplier * kHeight), 2);
    if (depth >= 0.2 * kHeight) {
      sum += std::abs(error / exact);
      ++counted;
    }
  }
  result.mean_error = sum / counted;
  result.rms_error = std::sqrt(squares / static_cast<double>(p.size()));
  return result;
}

void check_convergence(Geometry geometry, const char* label) {
  const int meshes[3] = {16, 32, 64};
  ColumnResult results[3];
  for (int m = 0; m < 3; ++m) {
    results[m] = run_column(geometry, meshes[m], ShapeFunction::cpgimp);
    std::printf(
        "[ column %s ] %2d cells: mean error %.3e, rms error %.3e, steps %ld, energy "
        "residual %.2e\n",
        label, meshes[m], results[m].mean_error, results[m].rms_error, results[m].steps,
        results[m].energy_residual);
    EXPECT_LT(results[m].energy_residual, 0.01) << label << " " << meshes[m];
    EXPECT_LT(results[m].lateral_ratio_error, 1e-5) << label << " " << meshes[m];
  }
  for (int m = 1; m < 3; ++m) {
    const double order = std::log2(results[m - 1].mean_error / results[m].mean_error);
    std::printf("[ column %s ] observed order %d -> %d cells: %.2f (mean), %.2f (rms)\n", label,
                meshes[m - 1], meshes[m], order,
                std::log2(results[m - 1].rms_error / results[m].rms_error));
    EXPECT_LT(results[m].mean_error, results[m - 1].mean_error) << label;
    EXPECT_LT(results[m].rms_error, results[m - 1].rms_error) << label;
  }
  EXPECT_LT(results[2].mean_error, 0.01) << label;
  for (int m = 1; m < 3; ++m)  // first order (see the top of the file)
    EXPECT_GT(std::log2(results[m - 1].mean_error / results[m].mean_error), 0.8) << label;
}

TEST(ColumnSelfWeight, PlaneStrainConvergesToTheWeightOfTheOverburden) {
  check_convergence(Geometry::plane_strain, "plane strain");
}

TEST(ColumnSelfWeight, AxisymmetricConvergesToTheWeightOfTheOverburden) {
  check_convergence(Geometry::axisymmetric, "axisymmetric");
}

// The centrifuge: N g with the stiffness N E is the same column in a time N^1/2 shorter, so every
// stress is N times the 1 g one (to round-off; the CFL step shrinks by N^1/2 alike).
TEST(ColumnSelfWeight, GravityMultiplierScalesTheStress) {
  std::vector<double> one_g, forty_g;
  run_column(Geometry::axisymmetric, 16, ShapeFunction::cpgimp, 1.0, &one_g, 400);
  run_column(Geometry::axisymmetric, 16, ShapeFunction::cpgimp, 40.0, &forty_g, 400);
  ASSERT_EQ(one_g.size(), forty_g.size());
  double largest = 0.0;
  const double scale = kDensity * kGravity * kHeight;
  for (std::size_t i = 0; i < one_g.size(); ++i)
    largest = std::max(largest, std::abs(forty_g[i] / 40.0 - one_g[i]) / scale);
  std::printf("[ column, 40 g ] largest |σ_40g / 40 - σ_1g| / (ρ g H) = %.2e\n", largest);
  EXPECT_LT(largest, 1e-9);
}

}  // namespace
}  // namespace pilempm::mpm
