// MPM case files run with [solver] analysis = "quasi-static" (docs/mpm-case-files.md,
// "Analyses"): the self-weight column against its closed form in one load step, a plate pushed
// into a block in load steps that land exactly on the displacement goal with the soil's vertical
// forces in balance at every step, load_steps.csv with the Newton work of each load step, a
// restart that continues bitwise, and the keys of the other analysis refused with the file, line
// and key.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/files.hpp"
#include "../support/input_texts.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_case_writer.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/simulation/case_assembly.hpp"
#include "pilempm/simulation/quasi_static_scheme.hpp"
#include "pilempm/simulation/run_loop.hpp"

namespace pilempm {
namespace {

using namespace simulation;
namespace fs = std::filesystem;

// An elastic column 1 m high, stress free, under its own weight.
std::string column_case() {
  using namespace test_support;
  return mpm_case_opening({.x_max_m = 0.4,
                           .x_cells = 4,
                           .y_max_m = 1.2,
                           .y_cells = 12,
                           .solver = "analysis = \"quasi-static\"\nthreads = 1\n"}) +
         linear_elastic_material_text("soil", 10.0) +
         mpm_region_text(
             {.x_max_m = 0.4, .y_max_m = 1.0, .material = "soil", .initial_stress = "zero"}) +
         R"([[phase]]
name = "self-weight"
duration_s = 1.0
energy_interval_s = 1.0
)";
}

using test_support::fresh_temp_path;
using test_support::read_text;
using test_support::replaced;

// The message of the InputError that reading `text` throws ("" when none).
std::string read_error(const std::string& text) {
  try {
    read_mpm_case_text(text, "case.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The explicit restart test's plate pushed into an elastic block under a surcharge, then lifted
// until its force falls below 1 kN with a stiffer set, run quasi-statically: pushed 4.5 mm in
// load steps of at most 1 mm.
std::string plate_case() {
  return replaced(replaced(test_support::plate_into_block_case(), "[solver]\nlocal_damping = 0.1\n",
                           "[solver]\nanalysis = \"quasi-static\"\ndisplacement_step_m = 0.001\n"),
                  "energy_interval_s = 0.005\n[phase.body.plate]",
                  "energy_interval_s = 0.005\nstop_displacement_y_m = -0.0045\n[phase.body.plate]");
}

TEST(QuasiStaticMpmCase, SelfWeightColumnMatchesTheClosedFormInOneLoadStep) {
  const MpmCase c = read_mpm_case_text(column_case(), "column.toml");
  ASSERT_EQ(c.analysis, MpmAnalysis::quasi_static);
  QuasiStaticScheme scheme(c);
  const std::vector<mpm::Vec2> start = scheme.state().particles().position;
  const std::vector<MpmPhaseEnd> ends = run_phases(c, scheme, 0, {});
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_EQ(ends[0].reason, "duration_s");
  EXPECT_EQ(scheme.steps(), 1);  // nothing moves: one load step to the phase end
  EXPECT_DOUBLE_EQ(scheme.time(), 1.0);
  // σ_yy = −ρ g (H − y) at every particle (y where it started: the strains are 0.2 %), within
  // ρ g h / 4 (h the cell, the bound of the solver's own column test, docs/verification.md);
  // the oedometric σ_xx = ν / (1 − ν) σ_yy to round-off.
  const mpm::Particles& p = scheme.state().particles();
  const double base = 2000.0 * 9.81 * 1.0;
  double worst = 0.0, worst_ratio = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double expected = -2000.0 * 9.81 * (1.0 - start[i].y());
    worst = std::max(worst, std::abs(p.state[i].stress[k22] - expected));
    worst_ratio = std::max(worst_ratio,
                           std::abs(p.state[i].stress[k11] / p.state[i].stress[k22] - 0.3 / 0.7));
  }
  EXPECT_LT(worst, 2000.0 * 9.81 * 0.1 / 4.0 * (1.0 + 1e-6));
  EXPECT_LT(worst_ratio, 1e-6);
  // The base carries the weight: ρ g H per metre times the width.
  EXPECT_NEAR(scheme.state().boundary_reaction().y(), base * 0.4, 1e-5 * base * 0.4);
}

// An observer that checks the soil's vertical balance at every record: the base's reaction
// carries the weight, the surcharge and the plate's force.
class VerticalBalance final : public RunObserver {
 public:
  explicit VerticalBalance(double weight_and_surcharge) : load_(weight_and_surcharge) {}
  void record(const Scheme& scheme, const MpmPhase& /*phase*/) override {
    const mpm::MpmState& s = scheme.state();
    if (s.steps() == 0) return;
    const double expected = load_ + s.rigid_body_force(0).total.y();
    worst_ = std::max(worst_, std::abs(s.boundary_reaction().y() - expected) / expected);
    ++records_;
  }
  double worst() const { return worst_; }
  int records() const { return records_; }

 private:
  double load_;
  double worst_ = 0.0;
  int records_ = 0;
};

TEST(QuasiStaticMpmCase, PlateLandsOnItsDisplacementGoalWithTheForcesInBalance) {
  const MpmCase c = read_mpm_case_text(plate_case(), "plate.toml");
  QuasiStaticScheme scheme(c);
  double mass = 0.0;
  for (double m : scheme.state().particles().mass) mass += m;
  VerticalBalance balance(mass * 9.81 + 5.0e3 * 1.0);
  const std::vector<MpmPhaseEnd> ends = run_phases(c, scheme, 0, {&balance});
  ASSERT_EQ(ends.size(), 2u);
  EXPECT_NE(ends[0].reason.find("stop_displacement_y_m"), std::string::npos) << ends[0].reason;
  // 4.5 mm in steps of at most 1 mm, with the records every 0.5 mm as further step ends.
  EXPECT_GE(ends[0].steps, 5);
  EXPECT_NE(ends[1].reason.find("stop_force_y_below_N"), std::string::npos) << ends[1].reason;
  // The lift ends where the force crosses 1 kN, found within 2.4e-4 of the load step's change
  // of force (about 9.3 kN in the step here: 2.3 N) on the side that meets the rule.
  const double force = scheme.state().rigid_body_force(0).total.y();
  EXPECT_LT(force, 1000.0);
  EXPECT_GT(force, 1000.0 - 2.3);
  // Equilibrium at the end of every load step to the Newton tolerance (1e-6 of the forces).
  EXPECT_GT(balance.records(), 10);
  EXPECT_LT(balance.worst(), 1e-5);
  EXPECT_GT(scheme.total_iterations(), 0);
}

TEST(QuasiStaticMpmCase, PlateStopsExactlyOnTheGoal) {
  const MpmCase c = read_mpm_case_text(plate_case(), "plate.toml");
  QuasiStaticScheme scheme(c);
  scheme.begin_phase(0);
  Advance advance;
  while (advance.stop_reason.empty()) advance = scheme.advance(c.phases[0].duration);
  EXPECT_EQ(scheme.state().rigid_body(0).displacement().y(), -0.0045);
  EXPECT_EQ(scheme.steps(), 5);  // 1, 1, 1, 1 and the last 0.5 mm
  EXPECT_GT(scheme.state().rigid_body_force(0).total.y(), 0.0);
}

// The rows of a CSV file without its comment line and header, split at commas.
std::vector<std::vector<std::string>> csv_rows(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::string line;
  std::vector<std::vector<std::string>> rows;
  int header = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header++ == 0) continue;
    std::vector<std::string> cells;
    std::istringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(QuasiStaticMpmCase, LoadStepsFileHasOneRowPerLoadStepWithItsNewtonWork) {
  const MpmCase c = read_mpm_case_text(plate_case(), "plate.toml");
  const fs::path out = fresh_temp_path("qs-load-steps");
  const MpmRunSummary run = run_mpm_case(c, out, nullptr);
  ASSERT_EQ(run.load_steps_file, out / "load_steps.csv");
  const std::vector<std::vector<std::string>> rows = csv_rows(run.load_steps_file);
  // time_s,step,phase,solves,iterations,cuts,accepted,largest_accepted_residual,stabilised,
  // stabilisation_share,rescued,unknowns,penetration_m,material_s,assembly_s,factorisation_s,
  // wall_s
  ASSERT_EQ(long(rows.size()), run.steps);
  long iterations = 0, cuts = 0, bisected = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 17u);
    EXPECT_EQ(rows[k][8], "0");  // no low-stress stabilisation
    EXPECT_EQ(std::stod(rows[k][9]), 0.0);
    EXPECT_EQ(rows[k][10], "0");
    EXPECT_EQ(std::stol(rows[k][1]), long(k) + 1);  // the load step that ended there
    iterations += std::stol(rows[k][4]);
    cuts += std::stol(rows[k][5]);
    EXPECT_GT(std::stoi(rows[k][11]), 0);
    const int solves = std::stoi(rows[k][3]);
    if (solves == 1) continue;
    // The lift's last step, where the force crosses 1 kN: solved, then solved again at
    // shorter lengths by regula falsi until the force lies within 2.4e-4 of the step's change
    // of force (here the plate leaves the sand within the step: the force is not linear in the
    // length). A bisection to that resolution takes 14 solves.
    EXPECT_GE(solves, 2);
    EXPECT_LE(solves, 8);
    EXPECT_EQ(k + 1, rows.size());
    EXPECT_EQ(rows[k][2], c.phases[1].name);
    ++bisected;
  }
  EXPECT_EQ(bisected, 1);
  EXPECT_EQ(iterations, run.newton_iterations);
  EXPECT_EQ(cuts, run.newton_cuts);
  EXPECT_GT(iterations, 0);
  fs::remove_all(out);
  // The explicit analysis has no such file.
  const std::string text =
      replaced(plate_case(), "analysis = \"quasi-static\"\ndisplacement_step_m = 0.001\n", "");
  EXPECT_TRUE(run_mpm_case(read_mpm_case_text(text, "explicit.toml"), out, nullptr)
                  .load_steps_file.empty());
  EXPECT_FALSE(fs::exists(out / "load_steps.csv"));
  fs::remove_all(out);
}

// Also with the low-stress stabilisation acting on the whole block (p_s above every stress): its
// reference, the strains of the last push step, goes into the checkpoint, so that the lift that
// reverses the plate after the restart starts its solves from the same stabilised solutions.
TEST(QuasiStaticMpmCase, RestartFromTheFirstPhaseEndsWithTheSameOutput) {
  const std::string plain = plate_case();
  const std::string stabilised =
      replaced(plain, "displacement_step_m = 0.001\n",
               "displacement_step_m = 0.001\nlow_stress_stiffness = 0.5\n"
               "low_stress_pressure_Pa = 1.0e7\nlow_stress_use = \"every_step\"\n");
  ASSERT_NE(stabilised, plain);
  long plain_iterations = 0;
  for (const std::string& text : {plain, stabilised}) {
    SCOPED_TRACE(text == plain ? "without stabilisation" : "with the low-stress stabilisation");
    const MpmCase c = read_mpm_case_text(text, "plate.toml");
    const fs::path whole = fresh_temp_path("qs-whole");
    const MpmRunSummary full = run_mpm_case(c, whole, nullptr);
    EXPECT_EQ(full.analysis, MpmAnalysis::quasi_static);
    ASSERT_EQ(full.checkpoints.size(), 2u);
    const fs::path second = fresh_temp_path("qs-restarted");
    const MpmRunSummary part = run_mpm_case(c, second, nullptr, full.checkpoints[0]);
    EXPECT_EQ(part.steps, full.steps);
    EXPECT_EQ(part.time, full.time);
    EXPECT_EQ(read_text(second / "energies.csv"), read_text(whole / "energies.csv"));
    EXPECT_EQ(read_text(second / "bodies.csv"), read_text(whole / "bodies.csv"));
    // load_steps.csv goes on from the checkpoint's rows: the same rows but for the timings.
    const auto whole_steps = csv_rows(whole / "load_steps.csv");
    const auto part_steps = csv_rows(second / "load_steps.csv");
    ASSERT_EQ(part_steps.size(), whole_steps.size());
    for (std::size_t k = 0; k < whole_steps.size(); ++k)
      for (std::size_t column = 0; column < 13; ++column)
        EXPECT_EQ(part_steps[k][column], whole_steps[k][column]) << k << ", " << column;
    if (text == stabilised) {
      // The stabilisation did act: each sub-increment was solved with it and again without it,
      // which converged (none kept the stabilising stress, so no damping is booked).
      long iterations = 0;
      for (const auto& row : whole_steps) {
        iterations += std::stol(row[4]);
        EXPECT_EQ(row[8], "0");
      }
      EXPECT_GT(iterations, plain_iterations);
      EXPECT_EQ(csv_rows(whole / "energies.csv").back()[6], "0") << "damping_J";
    } else {
      for (const auto& row : whole_steps)
        plain_iterations +=
            std::stol(row[4]);  // an explicit case cannot continue a quasi-static checkpoint
      const MpmCase explicit_case = read_mpm_case_text(
          replaced(plain, "analysis = \"quasi-static\"\ndisplacement_step_m = 0.001\n", ""),
          "explicit.toml");
      try {
        run_mpm_case(explicit_case, fresh_temp_path("qs-mixed"), nullptr, full.checkpoints[0]);
        ADD_FAILURE() << "no error";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("analysis"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("quasi-static"), std::string::npos) << e.what();
      }
    }
    for (const fs::path& dir : {whole, second, fresh_temp_path("qs-mixed")}) fs::remove_all(dir);
  }
}

TEST(QuasiStaticMpmCase, KeysOfTheOtherAnalysisAreErrors) {
  std::string message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\nmass_scaling = 2"));
  EXPECT_NE(message.find("solver.mass_scaling"), std::string::npos) << message;
  EXPECT_NE(message.find("explicit"), std::string::npos) << message;
  EXPECT_NE(message.find("case.toml:"), std::string::npos) << message;

  message = read_error(
      replaced(column_case(), "duration_s = 1.0", "duration_s = 1.0\nlocal_damping = 0.1"));
  EXPECT_NE(message.find("local_damping"), std::string::npos) << message;

  message = read_error(
      replaced(column_case(), "analysis = \"quasi-static\"", "displacement_step_m = 0.1"));
  EXPECT_NE(message.find("solver.displacement_step_m"), std::string::npos) << message;
  EXPECT_NE(message.find("quasi-static"), std::string::npos) << message;

  message =
      read_error(replaced(column_case(), "analysis = \"quasi-static\"", "analysis = \"implicit\""));
  EXPECT_NE(message.find("solver.analysis"), std::string::npos) << message;

  // volumetric_smoothing is B-bar in the quasi-static analysis; the Newton step limit is its own.
  const MpmCase smoothed = read_mpm_case_text(
      replaced(column_case(), "threads = 1",
               "threads = 1\nvolumetric_smoothing = true\nnewton_step_limit_cells = 0.1\n"
               "contact_vertex_radius_cells = 0.25\ncontact_smoothing = 0.05"),
      "smoothed.toml");
  EXPECT_TRUE(quasi_static_settings(smoothed).volumetric_averaging);
  EXPECT_EQ(smoothed.quasi_static.step_limit, 0.1);
  EXPECT_EQ(smoothed.quasi_static.contact.vertex_radius, 0.25);
  EXPECT_EQ(smoothed.quasi_static.contact.smoothing, 0.05);
  EXPECT_EQ(read_mpm_case_text(column_case(), "plain.toml").quasi_static.contact.vertex_radius,
            0.5);
  EXPECT_EQ(read_mpm_case_text(column_case(), "plain.toml").quasi_static.accept_tolerance, 1e-3);
  EXPECT_EQ(read_mpm_case_text(
                replaced(column_case(), "threads = 1", "threads = 1\naccept_tolerance = 0"),
                "strict.toml")
                .quasi_static.accept_tolerance,
            0.0);
  message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\naccept_tolerance = 0.5"));
  EXPECT_NE(message.find("solver.accept_tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("0.1"), std::string::npos) << message;
  message = read_error(
      replaced(column_case(), "threads = 1", "threads = 1\ncontact_vertex_radius_cells = 3"));
  EXPECT_NE(message.find("solver.contact_vertex_radius_cells"), std::string::npos) << message;
  message = read_error(
      replaced(column_case(), "analysis = \"quasi-static\"", "newton_step_limit_cells = 0.1"));
  EXPECT_NE(message.find("solver.newton_step_limit_cells"), std::string::npos) << message;

  // Inertia-driven: an initial velocity.
  const MpmCase moving =
      read_mpm_case_text(replaced(column_case(), "initial_stress = \"zero\"",
                                  "initial_stress = \"zero\"\nvelocity_y_m_per_s = -1.0"),
                         "moving.toml");
  try {
    QuasiStaticScheme scheme(moving);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("velocity"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("explicit"), std::string::npos) << e.what();
  }
}

// Newton's two tolerances: the energy norm falls as the square of the residual, so without its
// own key the energy tolerance follows the force tolerance (100 f², the defaults' pair 1e-6,
// 1e-10); given, it is kept; the written case reads back with both. The stall rule: off unless
// given. The tangent reuse: 0.1 unless given, in [0, 0.5].
TEST(QuasiStaticMpmCase, NewtonsTolerancesAndStallRuleAreKeys) {
  const auto settings = [](const std::string& keys) {
    return read_mpm_case_text(replaced(column_case(), "threads = 1", "threads = 1\n" + keys),
                              "case.toml")
        .quasi_static;
  };
  const mpm::quasi_static::Settings plain = settings("");
  EXPECT_EQ(plain.force_tolerance, 1e-6);
  EXPECT_EQ(plain.energy_tolerance, 1e-10);
  const mpm::quasi_static::Settings loose = settings("force_tolerance = 1e-4");
  EXPECT_EQ(loose.force_tolerance, 1e-4);
  EXPECT_EQ(loose.energy_tolerance, 1e-6);
  const mpm::quasi_static::Settings both =
      settings("force_tolerance = 1e-4\nenergy_tolerance = 1e-12");
  EXPECT_EQ(both.energy_tolerance, 1e-12);
  // A pair that is not the derived one survives the written file: the writer writes it.
  const MpmCase pair = read_mpm_case_text(
      mpm_case_text(read_mpm_case_text(
          replaced(column_case(), "threads = 1",
                   "threads = 1\nforce_tolerance = 1e-4\nenergy_tolerance = 1e-12"),
          "case.toml")),
      "written.toml");
  EXPECT_EQ(pair.quasi_static.energy_tolerance, 1e-12);
  // The derived value of the largest force tolerance is in the key's range.
  EXPECT_EQ(settings("force_tolerance = 0.1").energy_tolerance, 1.0);
  const MpmCase written = read_mpm_case_text(
      mpm_case_text(read_mpm_case_text(
          replaced(column_case(), "threads = 1", "threads = 1\nforce_tolerance = 1e-5"),
          "case.toml")),
      "written.toml");
  EXPECT_EQ(written.quasi_static.force_tolerance, 1e-5);
  EXPECT_EQ(written.quasi_static.energy_tolerance, 1e-8);

  EXPECT_EQ(plain.tangent_reuse, 0.1);
  EXPECT_EQ(settings("tangent_reuse = 0").tangent_reuse, 0.0);
  const std::string reuse_message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\ntangent_reuse = -0.1"));
  EXPECT_NE(reuse_message.find("solver.tangent_reuse"), std::string::npos) << reuse_message;
  EXPECT_NE(reuse_message.find("[0, 0.5]"), std::string::npos) << reuse_message;
  // strain_increment: the midpoint configuration's by default, or the start configuration's;
  // a case written out keeps it.
  EXPECT_TRUE(plain.midpoint_strain);
  EXPECT_FALSE(settings("strain_increment = \"start\"").midpoint_strain);
  EXPECT_FALSE(read_mpm_case_text(mpm_case_text(read_mpm_case_text(
                                      replaced(column_case(), "threads = 1",
                                               "threads = 1\nstrain_increment = \"start\""),
                                      "case.toml")),
                                  "written.toml")
                   .quasi_static.midpoint_strain);
  const std::string measure_message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\nstrain_increment = \"end\""));
  EXPECT_NE(measure_message.find("solver.strain_increment"), std::string::npos) << measure_message;
  EXPECT_NE(measure_message.find("midpoint"), std::string::npos) << measure_message;
  EXPECT_EQ(plain.stall_iterations, 0);
  EXPECT_EQ(settings("stall_iterations = 5").stall_iterations, 5);
  std::string message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\nstall_iterations = -1"));
  EXPECT_NE(message.find("solver.stall_iterations"), std::string::npos) << message;
  message =
      read_error(replaced(column_case(), "threads = 1", "threads = 1\nenergy_tolerance = 1.5"));
  EXPECT_NE(message.find("solver.energy_tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("[1e-24, 1]"), std::string::npos) << message;
  message =
      read_error(replaced(column_case(), "analysis = \"quasi-static\"", "energy_tolerance = 1e-8"));
  EXPECT_NE(message.find("solver.energy_tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("quasi-static"), std::string::npos) << message;
}

// [solver] linear_solver: the build's fastest by default; each one the build has by name; any
// other name an error with the allowed ones; a name the build lacks an error naming the default.
TEST(QuasiStaticMpmCase, LinearSolverIsAKeyWithTheBuildsSolvers) {
  using mpm::quasi_static::LinearSolverKind;
  const auto with_solver = [](const std::string& name) {
    return replaced(column_case(), "threads = 1", "threads = 1\nlinear_solver = \"" + name + "\"");
  };
  EXPECT_EQ(read_mpm_case_text(column_case(), "case.toml").quasi_static.linear_solver,
            mpm::quasi_static::default_linear_solver());
  for (const LinearSolverKind kind : mpm::quasi_static::kLinearSolverKinds) {
    const std::string name = mpm::quasi_static::to_string(kind);
    if (!mpm::quasi_static::linear_solver_available(kind)) {
      const std::string message = read_error(with_solver(name));
      EXPECT_NE(message.find("this build has no " + name), std::string::npos) << message;
      continue;
    }
    const MpmCase read = read_mpm_case_text(with_solver(name), "case.toml");
    EXPECT_EQ(read.quasi_static.linear_solver, kind) << name;
    // Written back (by name where it is not the default) and read again: the same solver.
    EXPECT_EQ(read_mpm_case_text(mpm_case_text(read), "written.toml").quasi_static.linear_solver,
              kind)
        << name;
  }
  const std::string message = read_error(with_solver("pardiso"));
  EXPECT_NE(message.find("solver.linear_solver"), std::string::npos) << message;
  EXPECT_NE(message.find("pardiso"), std::string::npos) << message;
  for (const char* allowed : {"mumps", "umfpack", "sparse-lu"})
    EXPECT_NE(message.find(allowed), std::string::npos) << message;
}

}  // namespace
}  // namespace pilempm
