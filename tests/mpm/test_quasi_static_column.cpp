// Quasi-static analysis (docs/quasi-static.md), verification 1: a linear elastic column under its
// own weight, rollers on the sides (the axis in axisymmetry), fixed base, loaded from zero to N g
// in one load step. The closed form (small strain, 1D, constrained modulus M =
// E(1-ν)/((1+ν)(1-2ν))):
//   σ_yy(Y) = -N ρ g (H - Y),   u_y(Y) = -N ρ g (H Y - Y²/2) / M,   σ_xx = σ_33 = ν/(1-ν) σ_yy.
// With 2 x 2 particles per cell, GIMP is the linear hat in this state and the particle
// quadrature integrates the load exactly, so the nodal displacements are exact and the stress is
// constant per cell, exact at the cell centre and off by N ρ g h/4 at the particles: the stress
// converges with order 1, the displacement at the particles with order 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "../support/mpm_builders.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/quasi_static/footing_problem.hpp"
#include "pilempm/mpm/quasi_static/load_path.hpp"
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

namespace pilempm::mpm::quasi_static {
namespace {

constexpr double kHeight = 1.0;      // H [m]
constexpr double kDensity = 2000.0;  // ρ [kg/m^3]
constexpr double kYoung = 50.0e6;    // E [Pa]
constexpr double kPoisson = 0.3;

double constrained_modulus() {
  return kYoung * (1.0 - kPoisson) / ((1.0 + kPoisson) * (1.0 - 2.0 * kPoisson));
}

struct ColumnResult {
  double max_stress_error = 0.0;  // max |σ_yy - exact| / (N ρ g h / 4), 1 is the bound
  double stress_rms = 0.0;        // RMS (σ_yy - exact) / (N ρ g H)
  double displacement_rms = 0.0;  // RMS (u_y - exact) / |u_y(H)| at the particles
  double top_node_error = 0.0;    // |u_y(node at H) - exact| / |exact|
  double lateral_error = 0.0;     // max |σ_xx/σ_yy - K0|, |σ_33/σ_yy - K0|
  int iterations = 0;
  bool converged = false;
};

// The grid of a column of `cells` cells, H high and 2 cells wide (walls, a fixed base, 2 cells
// of room above).
Grid column_grid(int cells) {
  const double h = kHeight / cells;
  Grid grid(GridAxis::uniform(0.0, 2.0 * h, 2),
            GridAxis::uniform(0.0, kHeight + 2.0 * h, cells + 2));
  test_support::set_walls_and_fixed_base(grid);
  return grid;
}

// The plane-strain column's particles (2 × 2 a cell) on `grid` of cell size h.
Particles column_particles(const Grid& grid, double h) {
  return test_support::particle_block(
      grid, Geometry::plane_strain, test_support::block_fill(0.0, 2.0 * h, 0.0, kHeight, kDensity));
}

// The contact points of a solver's run state, (x, y) per point [m].
std::vector<double> contact_points(const QuasiStaticSolver& solver) {
  for (const auto& [name, values] : solver.run_state().scheme_arrays)
    if (name == "contact_corner_position_m") return values;
  ADD_FAILURE() << "no contact points in the run state";
  return {};
}

// The plane-strain elastic column of `cells` cells (2 cells wide, walls and a fixed base) on a
// solver with `settings`.
// The elastic column of the solver's control tests (cuts, stabilisation, contact points), whose
// expected values are the linear column's closed forms: the strain is taken on the start
// configuration (sym G, Settings::midpoint_strain off), which makes the column linear. The
// midpoint strain is checked on its own (MidpointStrain.*, SelfWeightWithTheMidpointStrain...).
std::unique_ptr<QuasiStaticSolver> elastic_column(int cells, Settings settings) {
  settings.midpoint_strain = false;
  const double h = kHeight / cells;
  Grid grid = column_grid(cells);
  Particles particles = column_particles(grid, h);
  auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  return std::make_unique<QuasiStaticSolver>(std::move(grid), std::move(particles),
                                             std::vector<ModelPtr>{model}, settings);
}

ColumnResult run_column(Geometry geometry, int cells, double gravity_multiplier,
                        bool midpoint_strain = false) {
  const double h = kHeight / cells;
  Grid grid = column_grid(cells);
  Particles particles = test_support::particle_block(
      grid, geometry, test_support::block_fill(0.0, 2.0 * h, 0.0, kHeight, kDensity));
  std::vector<double> start_y(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) start_y[p] = particles.position[p].y();

  Settings settings;
  settings.geometry = geometry;
  // The closed form is the small-strain one, which the start configuration's strain gives
  // exactly (a linear problem); the midpoint strain makes it geometrically nonlinear.
  settings.midpoint_strain = midpoint_strain;
  auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, settings);
  LoadStep load;
  load.gravity_multiplier = gravity_multiplier;
  const LoadStepResult step = solver.solve_step(load);

  ColumnResult result;
  result.converged = step.converged;
  result.iterations = step.iterations;
  const double weight = gravity_multiplier * kDensity * settings.gravity;
  const double m = constrained_modulus();
  const double k0 = kPoisson / (1.0 - kPoisson);
  auto exact_u = [&](double y) { return -weight * (kHeight * y - 0.5 * y * y) / m; };
  const Particles& p = solver.particles();
  double s2 = 0.0, u2 = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double y = start_y[i];
    const Vec6& s = p.state[i].stress;
    const double exact = -weight * (kHeight - y);
    result.max_stress_error =
        std::max(result.max_stress_error, std::abs(s[k22] - exact) / (weight * h / 4.0));
    s2 += std::pow((s[k22] - exact) / (weight * kHeight), 2);
    const double u = p.position[i].y() - y;
    u2 += std::pow((u - exact_u(y)) / exact_u(kHeight), 2);
    result.lateral_error = std::max(
        {result.lateral_error, std::abs(s[k11] / s[k22] - k0), std::abs(s[k33] / s[k22] - k0)});
  }
  result.stress_rms = std::sqrt(s2 / double(p.size()));
  result.displacement_rms = std::sqrt(u2 / double(p.size()));
  const int top = solver.grid().node_index(1, cells);
  result.top_node_error =
      std::abs(solver.last_node_displacement()[std::size_t(top)].y() - exact_u(kHeight)) /
      std::abs(exact_u(kHeight));
  return result;
}

void check_column(Geometry geometry) {
  std::vector<ColumnResult> results;
  for (int cells : {4, 8, 16}) {
    results.push_back(run_column(geometry, cells, 50.0));
    const ColumnResult& r = results.back();
    std::printf(
        "cells %2d: iterations %d, max stress error %.3f (of ρNgh/4), stress RMS %.2e, "
        "displacement RMS %.2e, top node %.1e, K0 %.1e\n",
        cells, r.iterations, r.max_stress_error, r.stress_rms, r.displacement_rms, r.top_node_error,
        r.lateral_error);
    ASSERT_TRUE(r.converged);
    // Equilibrium in one load step: linear elasticity converges in one Newton iteration.
    EXPECT_EQ(r.iterations, 1);
    EXPECT_LT(r.max_stress_error, 1.0 + 1e-6);
    EXPECT_LT(r.top_node_error, 1e-6);
    EXPECT_LT(r.lateral_error, 1e-6);
  }
  for (std::size_t k = 1; k < results.size(); ++k) {
    const double stress_order = std::log2(results[k - 1].stress_rms / results[k].stress_rms);
    const double displacement_order =
        std::log2(results[k - 1].displacement_rms / results[k].displacement_rms);
    std::printf("order: stress %.2f, displacement %.2f\n", stress_order, displacement_order);
    EXPECT_NEAR(stress_order, 1.0, 0.1);
    EXPECT_NEAR(displacement_order, 2.0, 0.15);
  }
}

TEST(QuasiStaticColumn, PlaneStrainSelfWeightInOneStepConvergesWithOrder) {
  check_column(Geometry::plane_strain);
}

TEST(QuasiStaticColumn, AxisymmetricSelfWeightInOneStepConvergesWithOrder) {
  check_column(Geometry::axisymmetric);
}

// The same column with the midpoint strain (Settings::midpoint_strain, the default): the load
// step is geometrically nonlinear, Newton's method converges in a few iterations, and the
// settlement differs from the small-strain closed form by a share of the order of the strain
// (the base's strain ε_b = ρ N g H / M): for a uniaxial stretch λ the midpoint strain is
// 2(λ − 1)/(λ + 1), which exceeds λ − 1 in compression by about (λ − 1)²/2.
TEST(QuasiStaticColumn, WithTheMidpointStrainTheSettlementDiffersFromTheSmallStrainOneByTheStrain) {
  const double base_strain = 50.0 * kDensity * 9.81 * kHeight / constrained_modulus();
  for (const Geometry geometry : {Geometry::plane_strain, Geometry::axisymmetric}) {
    const ColumnResult r = run_column(geometry, 8, 50.0, /*midpoint_strain=*/true);
    std::printf(
        "midpoint strain: iterations %d, top node %.2e of the closed form, base strain %.2e\n",
        r.iterations, r.top_node_error, base_strain);
    ASSERT_TRUE(r.converged);
    EXPECT_GE(r.iterations, 2);
    EXPECT_LE(r.iterations, 4);
    EXPECT_GT(r.top_node_error, 0.05 * base_strain);
    EXPECT_LT(r.top_node_error, 0.5 * base_strain);
  }
}

// One load step to 1 g of an elastic column's `particles` on `grid` (SparseLU): whether it
// converged, the condition number of its Newton matrix (dense SVD), the base reaction's error
// against the weight, and the highest particle at the end [m].
struct GravityStep {
  bool converged = false;
  std::string message;
  double condition = 0.0;
  double reaction_error = 0.0;  // |R_y - W| / W
  double top = 0.0;
};

GravityStep one_gravity_step(Grid grid, Particles particles, Settings settings) {
  double weight = 0.0;
  for (std::size_t p = 0; p < particles.size(); ++p) weight += particles.mass[p] * 9.81;
  settings.linear_solver = LinearSolverKind::sparse_lu;
  auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, settings);
  LoadStep load;
  load.gravity_multiplier = 1.0;
  const LoadStepResult step = solver.solve_step(load);
  GravityStep result;
  result.converged = step.converged;
  result.message = step.message;
  const Eigen::MatrixXd dense(solver.last_matrix());
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(dense);
  const auto& sigma = svd.singularValues();
  result.condition = sigma(0) / sigma(sigma.size() - 1);
  result.reaction_error = std::abs(solver.boundary_reaction().y() - weight) / weight;
  result.top = -1.0;
  for (std::size_t p = 0; p < solver.particles().size(); ++p)
    result.top = std::max(result.top, solver.particles().position[p].y());
  return result;
}

// Stabilisation of weakly supported nodes: the column's particles are lifted by a small fraction
// of a cell, so that the top layer's domains reach a row of nodes by that fraction only. Without
// ghost springs those nodes make the Newton matrix nearly singular (their equations carry
// weights of the order of the overlap squared); with them the condition number drops by orders
// of magnitude, while the base still carries the whole weight (the springs are internal) and
// the settlement of the top particle stays close to the closed form (closer than without).
struct LiftedColumn {
  double condition = 0.0;
  double reaction_error = 0.0;  // |R_y - W| / W
  double settlement = 0.0;      // of the top particle [m]
};

LiftedColumn lifted_column(double ghost_stiffness, double lift) {
  const int cells = 8;
  const double h = kHeight / cells;
  Grid grid = column_grid(cells);
  Particles particles = column_particles(grid, h);
  for (std::size_t p = 0; p < particles.size(); ++p) particles.position[p].y() += lift * h;
  Settings settings;
  settings.ghost_stiffness = ghost_stiffness;
  const GravityStep step = one_gravity_step(std::move(grid), std::move(particles), settings);
  EXPECT_TRUE(step.converged) << step.message;
  LiftedColumn result;
  result.condition = step.condition;
  result.reaction_error = step.reaction_error;
  result.settlement = kHeight - 0.25 * h + lift * h - step.top;
  return result;
}

TEST(QuasiStaticStabilisation, GhostSpringsBoundTheConditionWithoutLosingLoad) {
  const LiftedColumn bare = lifted_column(0.0, 0.002);
  const LiftedColumn ghost = lifted_column(1.0e-3, 0.002);
  std::printf(
      "lift 0.002 h: condition %.2e without ghost springs, %.2e with; reaction error %.1e "
      "/ %.1e; settlement %.6e / %.6e m\n",
      bare.condition, ghost.condition, bare.reaction_error, ghost.reaction_error, bare.settlement,
      ghost.settlement);
  EXPECT_GT(bare.condition, 100.0 * ghost.condition);
  EXPECT_LT(bare.reaction_error, 1e-8);
  EXPECT_LT(ghost.reaction_error, 1e-8);
  // Closed form at the top particle, Y = H - h/4 above the base: ρ g (H Y - Y²/2) / M.
  const double y = kHeight - 0.25 * kHeight / 8.0;
  const double exact = kDensity * 9.81 * (kHeight * y - 0.5 * y * y) / constrained_modulus();
  std::printf("settlement closed form %.6e m\n", exact);
  EXPECT_NEAR(ghost.settlement, exact, 5e-3 * exact);
  EXPECT_LE(std::abs(ghost.settlement - exact), std::abs(bare.settlement - exact));
}

// Settings::support_particles on the elastic column (8 cells, plane strain) with one more
// particle above its top, its domain two cells wide: it alone reaches the three nodes of the
// grid row above the column (4 unknowns beside the walls) and has 3 strain components, so the
// Newton matrix is singular whatever the particle's stiffness. The support measure
// (support_threshold) passes these nodes (the particle covers a good part of their volume);
// counting the particles that reach a node ties them by ghost springs to the column, and the
// load step converges with the weight on the base (the springs act between nodes).
GravityStep column_with_lone_particle(int support_particles) {
  const int cells = 8;
  const double h = kHeight / cells;
  Grid grid = column_grid(cells);
  Particles particles = column_particles(grid, h);
  // One particle (a sub-cell's volume and mass) above the column, its domain [0, 2h] across
  // and a quarter of a cell deep: x-weights 1/4, 1/2, 1/4 at the three nodes of each row (the
  // middle one without an x-gradient), enough for the support measure.
  fill_rectangle(particles, grid, Geometry::plane_strain,
                 test_support::block_fill(0.5 * h, h, kHeight + 0.5 * h, kHeight + h, kDensity));
  particles.position.back() = Vec2(h, kHeight + 0.75 * h);
  particles.half_size.back() = Vec2(h, 0.25 * h);
  particles.initial_half_size.back() = particles.half_size.back();
  Settings settings;
  settings.support_particles = support_particles;
  return one_gravity_step(std::move(grid), std::move(particles), settings);
}

TEST(QuasiStaticStabilisation, NodesThatOneParticleAloneReachesAreTiedByGhostSprings) {
  const GravityStep bare = column_with_lone_particle(0);
  const GravityStep counted = column_with_lone_particle(3);
  std::printf(
      "lone particle: condition %.2e without counting the particles, %.2e with; "
      "reaction error %.1e\n",
      bare.condition, counted.condition, counted.reaction_error);
  EXPECT_GT(bare.condition, 1.0e12);  // singular to round-off
  ASSERT_TRUE(counted.converged) << counted.message;
  EXPECT_LT(counted.condition, 1.0e8);
  EXPECT_LT(counted.reaction_error, 1e-8);
  // The counts and the stress-free sand's volume bound out of range are refused.
  Settings settings;
  settings.support_particles = -1;
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings.support_particles = 0;
  EXPECT_NO_THROW(settings.validate());
  for (const double ratio : {1.0, 0.5, -1.0, std::numeric_limits<double>::infinity()}) {
    settings.floor_volume_ratio = ratio;
    EXPECT_THROW(settings.validate(), InvalidValue) << ratio;
  }
  settings.floor_volume_ratio = 0.0;  // no bound
  EXPECT_NO_THROW(settings.validate());
}

// Settings::inside_body_weakness on the elastic column (8 cells, plane strain, 2 cells wide)
// lifted by 0.3 of a cell: the top particles' domains reach the grid row above the column, each
// of its nodes reached by several of them and with 9 % of its volume as support (so neither the
// support measure nor the count makes them weak), only with the tails of their shape functions.
// A plate lies over that row, not touching the particles. With the nodes inside it weak, ghost
// springs tie them to the column's top row: the Newton matrix gains a symmetric, positive
// semi-definite part (springs between node pairs) and nothing else changes; the base still
// carries the whole weight (the springs are internal).
struct PlateColumn {
  LoadStepResult step;
  Eigen::MatrixXd matrix;
  double reaction_error = 0.0;
};

PlateColumn column_under_plate(double inside_body_weakness) {
  const int cells = 8;
  const double h = kHeight / cells;
  Grid grid = column_grid(cells);
  Particles particles = column_particles(grid, h);
  double weight = 0.0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    particles.position[p].y() += 0.3 * h;
    weight += particles.mass[p] * 9.81;
  }
  Settings settings;
  settings.inside_body_weakness = inside_body_weakness;
  settings.linear_solver = LinearSolverKind::sparse_lu;
  auto model = std::make_shared<LinearElastic>(ElasticParameters{kYoung, kPoisson});
  QuasiStaticSolver solver(std::move(grid), std::move(particles), {model}, settings);
  solver.add_rigid_body(RigidBody::polygon({{-1.0, kHeight + 0.5 * h},
                                            {1.0, kHeight + 0.5 * h},
                                            {1.0, kHeight + 3.0 * h},
                                            {-1.0, kHeight + 3.0 * h}}));
  LoadStep load;
  load.gravity_multiplier = 1.0;
  load.body_displacement = {Vec2::Zero()};
  PlateColumn result;
  result.step = solver.solve_step(load);
  result.matrix = Eigen::MatrixXd(solver.last_matrix());
  result.reaction_error = std::abs(solver.boundary_reaction().y() - weight) / weight;
  return result;
}

TEST(QuasiStaticStabilisation, NodesInsideARigidBodyAreTiedByGhostSpringsWhenAsked) {
  const PlateColumn free = column_under_plate(0.0);
  const PlateColumn tied = column_under_plate(1.0);
  ASSERT_TRUE(free.step.converged) << free.step.message;
  ASSERT_TRUE(tied.step.converged) << tied.step.message;
  ASSERT_EQ(free.matrix.rows(), tied.matrix.rows());
  const Eigen::MatrixXd springs = tied.matrix - free.matrix;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(springs);
  std::printf(
      "nodes inside a plate: springs' part of K %.3e of K, its eigenvalues %.3e to %.3e; "
      "reaction error %.1e / %.1e\n",
      springs.norm() / free.matrix.norm(), eigen.eigenvalues().minCoeff(),
      eigen.eigenvalues().maxCoeff(), free.reaction_error, tied.reaction_error);
  EXPECT_GT(springs.norm(), 1e-6 * free.matrix.norm());  // the springs are there
  EXPECT_LT((springs - springs.transpose()).norm(), 1e-12 * springs.norm());
  EXPECT_GT(eigen.eigenvalues().minCoeff(), -1e-9 * springs.norm());
  EXPECT_LT(free.reaction_error, 1e-8);
  EXPECT_LT(tied.reaction_error, 1e-8);
  Settings settings;
  for (const double w : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    settings.inside_body_weakness = w;
    EXPECT_THROW(settings.validate(), InvalidValue) << w;
  }
}

// Settings::low_stress_stiffness on the elastic column (8 cells, plane strain) loaded from zero
// to 0.05 g and then held. Every particle starts stress-free (w = 1) and its stabilising stress
// η M C:Δε has the material's ν, so in load step 1 the column is elastic with the modulus
// (1 + η) M and settles u_el / (1 + η); each further step at the same load releases the last
// step's stabilising stress and sets one for its own increment, so that after n steps the
// settlement is u_el (1 − r^n), r = η / (1 + η), exactly at the nodes. The stabilising stress is
// internal: the base carries the weight in every step; its work is booked as damping, η times
// the strain work in step 1. With p_s below every loaded particle's stress the second
// step has none, and the column reaches u_el (p_s = 10⁻³ Pa here).
TEST(QuasiStaticStabilisation, TheLowStressStiffnessLagsTheSettlementAndKeepsTheLoad) {
  const int cells = 8;
  // A small load (0.05 g, a settlement of 7 µm): the updated geometry moves later steps by
  // 10⁻⁶ of the settlement (at 50 g by 10⁻³).
  const double h = kHeight / cells, eta = 0.5, gravity_multiplier = 0.05;
  const double weight = gravity_multiplier * kDensity * 9.81;
  const double u_el = weight * 0.5 * kHeight * kHeight / constrained_modulus();  // at H
  for (const double p_s : {1.0e12, 1.0e-3}) {
    Settings settings;
    settings.low_stress_stiffness = eta;
    settings.low_stress_use = StabilisationUse::every_step;
    settings.low_stress_pressure = p_s;
    settings.low_stress_resolve = false;  // keep the stabilised solutions
    const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, settings);
    QuasiStaticSolver& solver = *column;
    const int top = solver.grid().node_index(1, cells);
    LoadStep load;
    load.gravity_multiplier = gravity_multiplier;
    double settlement = 0.0;
    const double r = eta / (1.0 + eta);
    for (int n = 1; n <= 3; ++n) {
      const LoadStepResult step = solver.solve_step(load);
      ASSERT_TRUE(step.converged) << "step " << n;
      EXPECT_EQ(step.stabilised, int(step.sub_increments.size())) << "step " << n;
      settlement -= solver.last_node_displacement()[std::size_t(top)].y();
      const double expected =
          p_s > 1.0 ? u_el * (1.0 - std::pow(r, n)) : (n == 1 ? u_el / (1.0 + eta) : u_el);
      const double reaction = solver.boundary_reaction().y() / (weight * kHeight * 2.0 * h);
      std::printf(
          "p_s %.0e Pa, step %d: settlement / u_el %.9f (expected %.9f), base reaction / "
          "weight %.12f, damping / strain work %.6f\n",
          p_s, n, settlement / u_el, expected / u_el, reaction,
          solver.energies().damping / solver.energies().internal);
      EXPECT_NEAR(settlement, expected, 2e-5 * u_el) << "step " << n;
      EXPECT_NEAR(reaction, 1.0, 1e-9) << "step " << n;
      if (n == 1) {
        EXPECT_NEAR(solver.energies().damping / solver.energies().internal, eta, 1e-6);
      }
    }
  }
}

// By default the stabilisation only finds the way: each sub-increment solved with it is solved
// again without it from that solution, which for the elastic column converges, so the first
// step gives the exact settlement, no damping, and no sub-increment keeps the stabilising stress.
TEST(QuasiStaticStabilisation, TheResolveWithoutItLeavesTheExactSolution) {
  const int cells = 8;
  const double h = kHeight / cells, gravity_multiplier = 0.05;
  const double weight = gravity_multiplier * kDensity * 9.81;
  const double u_el = weight * 0.5 * kHeight * kHeight / constrained_modulus();
  Settings settings;
  settings.low_stress_stiffness = 0.5;
  settings.low_stress_use = StabilisationUse::every_step;
  settings.low_stress_pressure = 1.0e12;
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, settings);
  QuasiStaticSolver& solver = *column;
  LoadStep load;
  load.gravity_multiplier = gravity_multiplier;
  const LoadStepResult step = solver.solve_step(load);
  ASSERT_TRUE(step.converged);
  EXPECT_EQ(step.stabilised, 0);
  EXPECT_EQ(step.largest_stabilisation_share, 0.0);
  for (const SubIncrementRecord& sub : step.sub_increments) EXPECT_EQ(sub.stabilisation_share, 0.0);
  const double settlement =
      -solver.last_node_displacement()[std::size_t(solver.grid().node_index(1, cells))].y();
  EXPECT_NEAR(settlement, u_el, 2e-5 * u_el);
  EXPECT_NEAR(solver.boundary_reaction().y() / (weight * kHeight * 2.0 * h), 1.0, 1e-9);
  EXPECT_EQ(solver.energies().damping, 0.0);
}

// The solves with less of the stabilisation (Settings::low_stress_continuation) go on from each
// other's solution, and the last one that converges within the drift limit (5 cells) is kept.
// The elastic column under a load whose settlement without the stabilisation would be 20 cells:
// with η = 100 it settles u_el / 101, with 0.1 of it u_el / 11 (1.6 cells further), with 0.01
// of it u_el / 2 (8.2 cells further: beyond the limit; its base strain of 2.5 would also invert
// the lowest particles), so the solution of the share 0.1 is kept.
TEST(QuasiStaticStabilisation, TheContinuationKeepsTheSmallestShareWithinTheDriftLimit) {
  const int cells = 8;
  const double h = kHeight / cells, u_el = 20.0 * h;
  const double weight = 2.0 * constrained_modulus() * u_el / (kHeight * kHeight);
  Settings settings;
  settings.low_stress_stiffness = 100.0;
  settings.low_stress_use = StabilisationUse::every_step;
  settings.low_stress_pressure = 1.0e12;
  settings.low_stress_continuation = {0.1, 0.01};
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, settings);
  QuasiStaticSolver& solver = *column;
  LoadStep load;
  load.gravity_multiplier = weight / (kDensity * 9.81);
  const LoadStepResult step = solver.solve_step(load);
  ASSERT_TRUE(step.converged) << step.message;
  ASSERT_EQ(step.sub_increments.size(), 1u);
  EXPECT_EQ(step.stabilised, 1);
  EXPECT_EQ(step.sub_increments[0].stabilisation_share, 0.1);
  EXPECT_EQ(step.largest_stabilisation_share, 0.1);
  const double settlement =
      -solver.last_node_displacement()[std::size_t(solver.grid().node_index(1, cells))].y();
  EXPECT_NEAR(settlement, u_el / 11.0, 1e-6 * u_el);
  EXPECT_GT(solver.energies().damping, 0.0);  // the kept stabilising stress's work is booked

  // Shares that do not decrease below 1 are refused.
  settings.low_stress_continuation = {0.1, 0.1};
  EXPECT_THROW(settings.validate(), InvalidValue);
  settings.low_stress_continuation = {1.0};
  EXPECT_THROW(settings.validate(), InvalidValue);
}

// StabilisationUse::last_resort (the default): a step that converges without the stabilisation
// is solved exactly as with η = 0 (the same iterations, the same settlement to the bit, no
// damping), where every_step solves it twice. The elastic column under 0.05 g, p_s above every
// stress.
TEST(QuasiStaticStabilisation, AsALastResortItLeavesAConvergingStepAlone) {
  const int cells = 8;
  const auto run = [&](double eta, StabilisationUse use) {
    Settings settings;
    settings.low_stress_stiffness = eta;
    settings.low_stress_pressure = 1.0e12;
    settings.low_stress_use = use;
    const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, settings);
    LoadStep load;
    load.gravity_multiplier = 0.05;
    const LoadStepResult step = column->solve_step(load);
    EXPECT_TRUE(step.converged) << step.message;
    EXPECT_FALSE(step.rescued);
    EXPECT_EQ(column->energies().damping, 0.0);
    const double settlement =
        -column->last_node_displacement()[std::size_t(column->grid().node_index(1, cells))].y();
    return std::make_pair(step.iterations, settlement);
  };
  const auto plain = run(0.0, StabilisationUse::last_resort);
  const auto last_resort = run(0.5, StabilisationUse::last_resort);
  const auto every_step = run(0.5, StabilisationUse::every_step);
  EXPECT_EQ(last_resort.first, plain.first);
  EXPECT_EQ(last_resort.second, plain.second);
  EXPECT_GT(every_step.first, plain.first);
}

// A step whose cuts without the stabilisation run out is finished with it, from the size that
// first failed. The column of the continuation test above (20 cells of settlement without the
// stabilisation, beyond the drift limit of 5; 10 in a half step, still beyond), one cut allowed:
// the whole step fails, its half fails, and the step is then solved in one piece with η = 100 and
// the continuation, which keeps the share 0.1 (u_el / 11). Without η it stops.
TEST(QuasiStaticStabilisation, AsALastResortItFinishesAStepWhoseCutsRanOut) {
  const int cells = 8;
  const double h = kHeight / cells, u_el = 20.0 * h;
  const double weight = 2.0 * constrained_modulus() * u_el / (kHeight * kHeight);
  for (const double eta : {0.0, 100.0}) {
    Settings settings;
    settings.low_stress_stiffness = eta;
    settings.low_stress_pressure = 1.0e12;
    settings.low_stress_continuation = {0.1, 0.01};
    settings.max_cuts = 1;
    const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, settings);
    QuasiStaticSolver& solver = *column;
    LoadStep load;
    load.gravity_multiplier = weight / (kDensity * 9.81);
    const LoadStepResult step = solver.solve_step(load);
    std::printf("eta %g: converged %d, rescued %d, cuts %d, sub-increments %zu: %s\n", eta,
                int(step.converged), int(step.rescued), step.cuts, step.sub_increments.size(),
                step.message.c_str());
    if (eta == 0.0) {
      EXPECT_FALSE(step.converged);
      EXPECT_FALSE(step.rescued);
      continue;
    }
    ASSERT_TRUE(step.converged) << step.message;
    EXPECT_TRUE(step.rescued);
    EXPECT_EQ(step.cuts, 1);
    ASSERT_EQ(step.sub_increments.size(), 3u);
    EXPECT_FALSE(step.sub_increments[0].converged);
    EXPECT_EQ(step.sub_increments[1].fraction, 0.5);
    EXPECT_FALSE(step.sub_increments[1].converged);
    EXPECT_EQ(step.sub_increments[2].fraction, 1.0);
    EXPECT_TRUE(step.sub_increments[2].converged);
    EXPECT_EQ(step.sub_increments[2].stabilisation_share, 0.1);
    EXPECT_EQ(step.stabilised, 1);
    const double settlement =
        -solver.last_node_displacement()[std::size_t(solver.grid().node_index(1, cells))].y();
    EXPECT_NEAR(settlement, u_el / 11.0, 1e-6 * u_el);
  }
}

// A converged solution that turns a particle inside out is not taken but cut. The elastic column
// under a load whose strain at the base would be 1.2 in one step (det(I + G) < 0 there; the top
// settles 4.8 cells, within the drift limit): the step is cut, and in halves (each from the last
// configuration) no particle inverts; every volume stays positive.
TEST(QuasiStaticColumn, ASolutionThatTurnsAParticleInsideOutIsCut) {
  const int cells = 8;
  const double strain_at_base = 1.2;
  const double weight = strain_at_base * constrained_modulus() / kHeight;
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, Settings{});
  QuasiStaticSolver& solver = *column;
  LoadStep load;
  load.gravity_multiplier = weight / (kDensity * 9.81);
  const LoadStepResult step = solver.solve_step(load);
  ASSERT_TRUE(step.converged) << step.message;
  EXPECT_GE(step.cuts, 1);
  ASSERT_FALSE(step.sub_increments.empty());
  EXPECT_FALSE(step.sub_increments.front().converged);  // the whole step: inverted, cut
  for (std::size_t p = 0; p < solver.particles().size(); ++p)
    EXPECT_GT(solver.particles().volume[p], 0.0) << "particle " << p;
  EXPECT_NEAR(solver.boundary_reaction().y() / (weight * kHeight * 2.0 * kHeight / cells), 1.0,
              1e-9);
}

// The contact points (the corners of the particles' domains, carried with each particle's affine
// motion) are drawn back, along the segment to their particle, within |l| of it along x and y
// (|l| the domain's half-diagonal, at most a cell) at the end of every sub-increment and at the
// start of each load step (for a checkpoint written before the bound): in MPM-2 the sand sheared
// along the shaft had carried them up to 22 cells from their particles, where ∇S_k · (x_q − x_p)
// multiplied a point's force on the nodes, and the nodes' motion at the point, by about 20. A
// checkpoint's contact point 20 cells away comes back to the bound in a load step of no load, and
// after a load step every point lies within it.
TEST(QuasiStaticColumn, ContactPointsStayNearTheirParticles) {
  const int cells = 4;
  const double h = kHeight / cells;
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, Settings{});
  QuasiStaticSolver& solver = *column;
  // The largest distance of a contact point beyond its particle's domain [m].
  const auto largest_excess = [&]() {
    const std::vector<double> points = contact_points(solver);
    const Particles& p = solver.particles();
    double excess = 0.0;
    for (std::size_t c = 0; 2 * c + 1 < points.size(); ++c) {
      const std::size_t i = c / 4;
      for (int a = 0; a < 2; ++a)
        excess = std::max(excess, std::abs(points[2 * c + std::size_t(a)] - p.position[i][a]) -
                                      std::min(p.half_size[i].norm(), h));
    }
    return excess;
  };
  EXPECT_LE(largest_excess(), 1e-15);

  SolverRunState state = solver.run_state();
  for (auto& [name, values] : state.scheme_arrays)
    if (name == "contact_corner_position_m") {
      values[0] += 20.0 * h;  // particle 0's first corner (−l_x, −l_y) carried 20 cells away
      values[1] -= 20.0 * h;
    }
  solver.restore_run_state(state);
  // A load step in which nothing changes: the point comes back to the bound at the start of the
  // step, and nothing else moves.
  LoadStep nothing;
  nothing.gravity_multiplier = 0.0;
  const LoadStepResult still = solver.solve_step(nothing);
  ASSERT_TRUE(still.converged) << still.message;
  const std::vector<double> restored = contact_points(solver);
  const Vec2& x = solver.particles().position[0];
  const double reach = solver.particles().half_size[0].norm();
  ASSERT_LT(reach, h);
  // Drawn back along the segment to the particle: the larger component (y) at the bound.
  const Vec2 offset(20.0 * h - solver.particles().half_size[0].x(),
                    -20.0 * h - solver.particles().half_size[0].y());
  const double scale = reach / std::abs(offset.y());
  EXPECT_NEAR(restored[0], x.x() + scale * offset.x(), 1e-15);
  EXPECT_NEAR(restored[1], x.y() - reach, 1e-15);
  EXPECT_LE(largest_excess(), 1e-15);

  LoadStep load;
  load.gravity_multiplier = 1.0;
  const LoadStepResult step = solver.solve_step(load);
  ASSERT_TRUE(step.converged) << step.message;
  EXPECT_LE(largest_excess(), 1e-15);
}

// A contact point drawn back to its particle is never moved into a body (nor deeper into one):
// the bound alone, clamping component by component, had moved points of sand at MPM-2's pile
// shoulder from beside the cone into the shaft (docs/quasi-static.md, "Contact with the exact
// surface"). A plate lies just above the column; the top particle's point, put 20 cells above the
// plate, is drawn back towards its particle and stops on the plate's top face instead of inside
// the plate.
TEST(QuasiStaticColumn, ABoundedContactPointIsNotMovedIntoABody) {
  const int cells = 4;
  const double h = kHeight / cells;
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(cells, Settings{});
  QuasiStaticSolver& solver = *column;
  const double bottom = kHeight + 0.05 * h, top = kHeight + 0.5 * h;
  solver.add_rigid_body(
      RigidBody::polygon({{-1.0, bottom}, {1.0, bottom}, {1.0, top}, {-1.0, top}}));
  std::size_t highest = 0;
  for (std::size_t p = 1; p < solver.particles().size(); ++p)
    if (solver.particles().position[p].y() > solver.particles().position[highest].y()) highest = p;
  const Vec2 x = solver.particles().position[highest];
  // Without the body, the point would come back to x + (0, |l|), inside the plate.
  ASSERT_GT(x.y() + solver.particles().half_size[highest].norm(), bottom);
  SolverRunState state = solver.run_state();
  for (auto& [name, values] : state.scheme_arrays)
    if (name == "contact_corner_position_m") {
      values[8 * highest + 6] = x.x();  // corner 3 (+l_x, +l_y)
      values[8 * highest + 7] = kHeight + 20.0 * h;
    }
  solver.restore_run_state(state);
  LoadStep nothing;
  nothing.gravity_multiplier = 0.0;
  nothing.body_displacement = {Vec2::Zero()};
  const LoadStepResult still = solver.solve_step(nothing);
  ASSERT_TRUE(still.converged) << still.message;
  for (const auto& [name, values] : solver.run_state().scheme_arrays)
    if (name == "contact_corner_position_m") {
      const Vec2 corner(values[8 * highest + 6], values[8 * highest + 7]);
      EXPECT_NEAR(corner.x(), x.x(), 1e-15);
      EXPECT_GE(corner.y(), top);          // on the plate's top face, not inside the plate
      EXPECT_LT(corner.y(), top + 1e-12);  // and no further out than that
    }
}

// A body put where particles are (a pile wished in place) moves the contact points that start
// inside it onto its surface along the surface's normal, to the nearest surface point, and leaves
// the others as they are. A plate whose tilted bottom face cuts the top corners of the column's
// top row (not their centres): drawn along the segment to the particle's centre instead, a point
// would move sideways by about its depth; along the normal it moves by 2 % of it.
TEST(QuasiStaticColumn,
     AWishedInPlaceBodyPlacesTheContactPointsInsideItOnItsSurfaceAlongTheNormal) {
  const std::unique_ptr<QuasiStaticSolver> column = elastic_column(4, Settings{});
  QuasiStaticSolver& solver = *column;
  const std::vector<double> before = contact_points(solver);
  // Bottom face y = 0.99 + 0.02 x: up to 0.01 m above the column's top (y = 1) at x < 0.5.
  const RigidBody plate =
      RigidBody::polygon({{-1.0, 0.97}, {1.0, 1.01}, {1.0, kHeight + 0.4}, {-1.0, kHeight + 0.4}});
  solver.add_rigid_body(plate);
  const std::vector<double> after = contact_points(solver);
  ASSERT_EQ(after.size(), before.size());
  int inside = 0;
  for (std::size_t c = 0; 2 * c + 1 < before.size(); ++c) {
    const Vec2 old_point(before[2 * c], before[2 * c + 1]);
    const Vec2 new_point(after[2 * c], after[2 * c + 1]);
    const SurfaceQuery hit = plate.query(old_point);
    if (!(hit.distance < 0.0)) {
      EXPECT_EQ(new_point, old_point) << "point " << c;
      continue;
    }
    ++inside;
    const Vec2 expected = old_point - hit.distance * hit.normal;
    EXPECT_NEAR(new_point.x(), expected.x(), 1e-15) << "point " << c;
    EXPECT_NEAR(new_point.y(), expected.y(), 1e-15) << "point " << c;
    EXPECT_NEAR(plate.query(new_point).distance, 0.0, 1e-15) << "point " << c;
    EXPECT_LT(std::abs(new_point.x() - old_point.x()), 0.03 * std::abs(hit.distance))
        << "point " << c;
  }
  EXPECT_GE(inside, 6);  // the top corners at x = 0 .. 0.375 of the four top particles
}

// Where a body moves, the stabilising stress resists only the change of a particle's strain
// increment from the last sub-increment in which the body moved (scaled by the share of that
// motion repeated), as inertia resists a change of velocity. An elastic layer (the strip
// footing's soil with a cohesion it never reaches) pushed by the smooth footing in equal steps,
// the stabilisation acting on every particle (p_s above every stress): in the first step there
// is no reference and the footing's force lags the unstabilised force; as the steps repeat the
// motion the lag fades, where resisting the whole increment would keep it.
TEST(QuasiStaticStabilisation, TheLowStressStiffnessFadesWhereTheMotionRepeats) {
  StripFootingProblem problem;
  problem.cohesion = 1.0e12;  // elastic
  problem.cells_under_footing = 4;
  const double h = problem.cell();
  const int steps = 10;
  std::vector<double> plain, stabilised;
  for (const double eta : {0.0, 0.5}) {
    problem.settings.low_stress_stiffness = eta;
    problem.settings.low_stress_use = StabilisationUse::every_step;
    problem.settings.low_stress_pressure = 1.0e12;
    problem.settings.low_stress_resolve = false;  // the stabilised solutions themselves
    QuasiStaticSolver solver = problem.build();
    for (const PushPoint& p : push_body(solver, 0, Vec2(0.0, -h / 16.0), steps, 0.0)) {
      ASSERT_TRUE(p.converged) << "eta " << eta << ": " << p.message;
      (eta > 0.0 ? stabilised : plain).push_back(p.force.y());
    }
  }
  ASSERT_EQ(plain.size(), std::size_t(steps));
  ASSERT_EQ(stabilised.size(), std::size_t(steps));
  // The stabilising stress adds to the soil's: under the footing's prescribed motion the
  // stabilised force exceeds the plain one.
  const double first_excess = stabilised[0] - plain[0];
  double later = 0.0;  // mean |excess| over steps 3 to 10
  for (int n = 0; n < steps; ++n) {
    const double excess = stabilised[std::size_t(n)] - plain[std::size_t(n)];
    std::printf("step %d: force %.6g N, stabilised %.6g N, excess / first excess %.3e\n", n + 1,
                plain[std::size_t(n)], stabilised[std::size_t(n)], excess / first_excess);
    if (n >= 2) later += std::abs(excess) / (steps - 2);
  }
  // The first step: the stabilising stiffness η M_c stands beside the soil's and adds a good
  // part of the step's force (measured: 47 %).
  EXPECT_GT(first_excess, 0.2 * plain[0]);
  // Then it fades (measured: 0.2-5 % of the first excess, 1.3 % on average; resisting the whole
  // increment would keep an excess of the first one's order in every step).
  EXPECT_LT(later, 0.03 * first_excess);
}

}  // namespace
}  // namespace pilempm::mpm::quasi_static
