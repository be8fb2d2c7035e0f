// `pilempm centrifuge` as a user runs it: `case` prints the MPM case a centrifuge case file
// becomes, a bad case file is an error naming the file, the line and the key, and `run` of the
// built-in quick case writes pile.csv, the fields and summary.json, whose checks hold.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include "run_pilempm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/scenario/centrifuge/experiment.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace {

using pilempm::test_support::TestDir;
using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

namespace fs = std::filesystem;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  return fields;
}

// A CSV file of pilempm: comment lines (#), the header, the rows (no quoted commas).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  std::size_t column(const std::string& name) const {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << name;
    return at == header.end() ? 0 : static_cast<std::size_t>(at - header.begin());
  }
  double number(std::size_t row, const std::string& name) const {
    return std::stod(rows.at(row).at(column(name)));
  }
  std::string text(std::size_t row, const std::string& name) const {
    std::string value = rows.at(row).at(column(name));
    if (value.size() >= 2 && value.front() == '"') value = value.substr(1, value.size() - 2);
    return value;
  }
};

Csv read_csv(const fs::path& path) {
  Csv csv;
  std::istringstream in(read_text(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.front() == '#') continue;
    if (csv.header.empty())
      csv.header = split(line, ',');
    else
      csv.rows.push_back(split(line, ','));
  }
  return csv;
}

// A number of summary.json ("key": value); NaN when missing or null.
double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return std::nan("");
  const char* start = json.c_str() + at + key.size() + 3;
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  return end == start ? std::nan("") : value;
}

// NumberOfPoints of a .vtu (-1 when missing).
long vtu_points(const fs::path& path) {
  const std::string text = read_text(path);
  const auto at = text.find("NumberOfPoints=\"");
  if (at == std::string::npos) return -1;
  return std::stol(text.substr(at + 16));
}

std::string quick_case_path() {
  return std::string(PILEMPM_SOURCE_DIR) + "/examples/centrifuge/quick.toml";
}

TEST(CentrifugeCli, CasePrintsTheMpmCaseOfTheQuickCase) {
  const Result r = run_pilempm("centrifuge case");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("[[body]]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("kind = \"axisymmetric\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[[phase]]"), std::string::npos) << r.output;

  // It is an MPM case file: read back, the pile and the phases of the scenario.
  const pilempm::simulation::MpmCase c = pilempm::read_mpm_case_text(r.output, "printed case");
  EXPECT_EQ(c.geometry, pilempm::mpm::Geometry::axisymmetric);
  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_EQ(c.bodies[0].name, "pile");
  const pilempm::scenario::CentrifugeScenario s = pilempm::read_centrifuge_case(quick_case_path());
  std::vector<std::string> phases;
  for (const pilempm::simulation::MpmPhase& p : c.phases) phases.push_back(p.name);
  EXPECT_EQ(phases, pilempm::scenario::scenario_phase_names(s));
  EXPECT_NEAR(c.bodies[0].tip_y, s.initial_tip_y(), 1e-9);

  // The built-in case is examples/centrifuge/quick.toml.
  const Result from_file = run_pilempm("centrifuge case '" + quick_case_path() + "'");
  ASSERT_EQ(from_file.exit_code, 0) << from_file.output;
  EXPECT_EQ(from_file.output, r.output);
  EXPECT_EQ(r.output, pilempm::centrifuge_mpm_case_text(
                          pilempm::scenario::centrifuge_case(s, "mpm_case.toml")));
}

TEST(CentrifugeCli, BadCaseFileIsAnErrorNamingTheFileTheLineAndTheKey) {
  const TestDir dir("centrifuge-cli");
  const fs::path file = dir.path() / "bad.toml";
  write_text(file, "[sand]\ne0 = 0.68\ne0_at = \"initial-stress\"\n[mesh]\ncell_per_D = 8\n");
  const Result run = run_pilempm("centrifuge run '" + file.string() + "' --out '" +
                                 (dir.path() / "out").string() + "' --quiet --no-plots");
  EXPECT_NE(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find(file.string() + ":5"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("mesh.cell_per_D"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "pile.csv"));
  const Result shown = run_pilempm("centrifuge case '" + file.string() + "'");
  EXPECT_NE(shown.exit_code, 0) << shown.output;
  EXPECT_NE(shown.output.find(file.string() + ":5"), std::string::npos) << shown.output;
  EXPECT_NE(shown.output.find("mesh.cell_per_D"), std::string::npos) << shown.output;
  EXPECT_EQ(shown.output.find("[[body]]"), std::string::npos) << shown.output;

  // A value out of range: the key, the value, the range.
  write_text(file, "[sand]\ne0 = -1\ne0_at = \"initial-stress\"\n");
  const Result range = run_pilempm("centrifuge case '" + file.string() + "'");
  EXPECT_NE(range.exit_code, 0) << range.output;
  EXPECT_NE(range.output.find(file.string() + ":2"), std::string::npos) << range.output;
  EXPECT_NE(range.output.find("sand.e0 = -1"), std::string::npos) << range.output;
  EXPECT_NE(range.output.find("(0, 5)"), std::string::npos) << range.output;

  // A file that is not there.
  const std::string missing = (dir.path() / "missing.toml").string();
  const Result none = run_pilempm("centrifuge case '" + missing + "'");
  EXPECT_NE(none.exit_code, 0) << none.output;
  EXPECT_NE(none.output.find(missing), std::string::npos) << none.output;
}

// Inside the pile of the quick case at the end of installation, `margin` [mm] inside its
// surface: r < R − margin and above the conical tip (60° apex: the cone rises r / tan 30° from
// the tip) by more than margin / sin 30° vertically (the normal distance to the cone is the
// vertical one times sin 30°).
bool inside_pile(double r_mm, double depth_mm, double tip_depth_mm, double margin_mm) {
  const double R = 0.5 * 11.3;
  const double pi = 3.14159265358979323846;
  const double half_apex = 30.0 * pi / 180.0;
  return r_mm < R - margin_mm &&
         depth_mm < tip_depth_mm - r_mm / std::tan(half_apex) - margin_mm / std::sin(half_apex);
}

// The quick case (R = 6 D, H = 12 D, D = 11.3 mm at 40 g, wished in place at 3 D, jacked 2 D in
// quasi-static load steps, relaxed, load-tested over 0.1 D): one run, checked through its files.
// About 45 s on two cores, hence Long.
TEST(CentrifugeCli, LongQuickCaseRunWritesConsistentPileForcesFieldsAndSummary) {
  const TestDir dir("centrifuge-cli");
  const fs::path out = dir.path() / "run";
  const Result r = run_pilempm("centrifuge run --out '" + out.string() + "' --quiet --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("built-in quick case"), std::string::npos) << r.output;
  const double D = 11.3;  // [mm]

  // pile.csv: the columns, then rows of the four phases in order.
  ASSERT_TRUE(fs::exists(out / "pile.csv"));
  const Csv pile = read_csv(out / "pile.csv");
  for (const char* column :
       {"time_s", "phase", "pile_displacement_mm", "phase_displacement_mm", "tip_depth_mm",
        "tip_depth_D", "head_force_N", "tip_force_N", "shaft_force_N", "tip_stress_MPa",
        "base_reaction_N", "soil_weight_N", "equilibrium_residual_N", "kinetic_J", "pile_work_J",
        "sand_momentum_rate_N", "damping_force_N"})
    EXPECT_NE(std::find(pile.header.begin(), pile.header.end(), column), pile.header.end())
        << column;
  ASSERT_GT(pile.rows.size(), 10u);
  std::vector<std::string> phases;
  for (std::size_t k = 0; k < pile.rows.size(); ++k) {
    EXPECT_EQ(pile.rows[k].size(), pile.header.size()) << "row " << k;
    const std::string phase = pile.text(k, "phase");
    if (phases.empty() || phases.back() != phase) phases.push_back(phase);
  }
  EXPECT_EQ(phases, (std::vector<std::string>{"initial-stress", "installation", "relaxation",
                                              "load-test"}));

  // The head force is the soil's force on the whole pile: tip and shaft (its top face, a
  // kilometre above the grid, touches nothing).
  double previous_time = -1.0;
  for (std::size_t k = 0; k < pile.rows.size(); ++k) {
    const double head = pile.number(k, "head_force_N");
    EXPECT_NEAR(head, pile.number(k, "tip_force_N") + pile.number(k, "shaft_force_N"),
                0.02 * std::abs(head) + 1.0)
        << "row " << k;
    EXPECT_GT(pile.number(k, "time_s"), previous_time) << "row " << k;
    previous_time = pile.number(k, "time_s");
    // The tip depth is the wished-in-place depth plus the displacement.
    EXPECT_NEAR(pile.number(k, "tip_depth_mm"), 3.0 * D + pile.number(k, "pile_displacement_mm"),
                1e-3)
        << "row " << k;
  }
  const Csv bodies = read_csv(out / "mpm" / "bodies.csv");
  ASSERT_FALSE(bodies.rows.empty());
  for (std::size_t k = 0; k < bodies.rows.size(); ++k)
    EXPECT_EQ(bodies.number(k, "force_y_head_N"), 0.0) << "bodies.csv row " << k;

  // Installation: the pile goes down only, to 2 D = 22.6 mm, pushed (head force > 0).
  double last_installation = -1.0, installation_head = 0.0;
  std::size_t installation_rows = 0;
  double relaxation_end = std::nan(""), load_start_head = std::nan(""), load_end_head = 0.0,
         load_end_travel = 0.0;
  for (std::size_t k = 0; k < pile.rows.size(); ++k) {
    const std::string phase = pile.text(k, "phase");
    const double displacement = pile.number(k, "pile_displacement_mm");
    if (phase == "installation") {
      EXPECT_GE(displacement, last_installation) << "row " << k;
      last_installation = displacement;
      installation_head = pile.number(k, "head_force_N");
      ++installation_rows;
    } else if (phase == "relaxation") {
      relaxation_end = displacement;
    } else if (phase == "load-test") {
      if (std::isnan(load_start_head)) load_start_head = pile.number(k, "head_force_N");
      load_end_head = pile.number(k, "head_force_N");
      load_end_travel = pile.number(k, "phase_displacement_mm");
    }
  }
  EXPECT_GE(installation_rows, 20u);  // a row per 0.05 D of travel
  EXPECT_NEAR(last_installation, 2.0 * D, 1e-3);
  EXPECT_GT(installation_head, 0.0);
  // Relaxation pulls it up, at most 0.05 D; the load test pushes it down 0.1 D, the force rising.
  EXPECT_LT(relaxation_end, last_installation);
  EXPECT_GT(relaxation_end, last_installation - 0.05 * D - 1e-3);
  EXPECT_NEAR(load_end_travel, 0.1 * D, 1e-3);
  EXPECT_GT(load_end_head, load_start_head);

  // summary.json: the checks and the results.
  const std::string summary = read_text(out / "summary.json");
  ASSERT_FALSE(summary.empty());
  EXPECT_LT(json_number(summary, "initial_stress_error"), 0.01) << summary;
  EXPECT_NEAR(json_number(summary, "initial_stress_ratio"), 1.0, 0.01) << summary;
  EXPECT_LT(json_number(summary, "equilibrium_error"), 0.02) << summary;
  EXPECT_LT(json_number(summary, "max_kinetic_to_work"), 0.01) << summary;
  EXPECT_GT(json_number(summary, "installation_head_force_N"), 0.0) << summary;
  EXPECT_NEAR(json_number(summary, "installation_tip_depth_D"), 5.0, 1e-6) << summary;
  EXPECT_GT(json_number(summary, "load_test_capacity_N"), 0.0) << summary;
  EXPECT_NEAR(json_number(summary, "load_test_capacity_N"), load_end_head,
              1e-4 * std::abs(load_end_head) + 1e-3)
      << summary;
  EXPECT_GT(json_number(summary, "relaxation_travel_mm"), 0.0) << summary;
  EXPECT_LE(json_number(summary, "relaxation_travel_mm"), 0.05 * D + 1e-3) << summary;
  // The head force's scatter over the last D is that of pile.csv's installation rows there.
  std::vector<double> last_travel, last_head;
  for (std::size_t k = 0; k < pile.rows.size(); ++k) {
    const double travel = pile.number(k, "pile_displacement_mm") / D;
    if (pile.text(k, "phase") != "installation" || travel < 1.0 - 1e-9) continue;
    last_travel.push_back(travel);
    last_head.push_back(pile.number(k, "head_force_N"));
  }
  const double scatter = pilempm::scenario::head_force_scatter(last_travel, last_head);
  ASSERT_GT(scatter, 0.0);
  EXPECT_NEAR(json_number(summary, "scatter_last_D"), scatter, 1e-4 * scatter) << summary;
  EXPECT_GE(json_number(summary, "largest_scatter"), json_number(summary, "scatter_last_D"));

  // The number of particles stays the same from the first snapshot to the last and in the
  // fields.
  const double particles = json_number(summary, "particles");
  EXPECT_GT(particles, 1000.0) << summary;
  std::vector<fs::path> snapshots;
  for (const auto& entry : fs::directory_iterator(out / "mpm"))  // not the bodies_*.vtu
    if (entry.path().extension() == ".vtu" &&
        entry.path().filename().string().starts_with("particles_"))
      snapshots.push_back(entry.path());
  std::sort(snapshots.begin(), snapshots.end());
  ASSERT_GE(snapshots.size(), 2u);
  EXPECT_EQ(vtu_points(snapshots.front()), static_cast<long>(particles));
  EXPECT_EQ(vtu_points(snapshots.back()), static_cast<long>(particles));
  EXPECT_EQ(vtu_points(out / "fields_installation.vtu"), static_cast<long>(particles));
  const Csv fields = read_csv(out / "fields_installation.csv");
  EXPECT_EQ(fields.rows.size(), static_cast<std::size_t>(particles));
  EXPECT_EQ(read_csv(out / "fields_load-test.csv").rows.size(),
            static_cast<std::size_t>(particles));

  // No particle inside the pile at the end of installation (tip 5 D deep). The quick case runs
  // on the quasi-static analysis, whose contact acts at points of the particles' domains (on the
  // explicit one, at the grid nodes), so particle centres next to the surface may lie a little
  // inside it; half a cell (a particle's width with 2 per cell) allows that, and a particle left
  // in the pile's path (up to R = 2 cells inside) is still caught.
  const double cell = D / 4.0;
  std::size_t inside = 0, near_surface = 0;
  for (std::size_t k = 0; k < fields.rows.size(); ++k) {
    const double r_mm = fields.number(k, "r_mm"), depth = fields.number(k, "depth_mm");
    if (inside_pile(r_mm, depth, 5.0 * D, 0.5 * cell)) {
      ++inside;
      ADD_FAILURE() << "particle " << k << " at r = " << r_mm << " mm, depth " << depth << " mm";
    }
    if (inside_pile(r_mm, depth, 5.0 * D, -cell)) ++near_surface;  // within a cell of it
    EXPECT_GT(fields.number(k, "void_ratio"), 0.0) << "particle " << k;
  }
  EXPECT_EQ(inside, 0u);
  EXPECT_GT(near_surface, 10u);  // the sand stays in touch with the pile
}

// The IGS study's cases with IGS 1 and IGS 3 on the quasi-static analysis: the pile starts at the
// sand surface and is jacked 4.7 D, through sand that heaves beside it and loses its stress. IGS 3
// stopped at 3.3 D before stress-free sand kept its volume bounded and the nodes one particle
// alone reaches got ghost springs (docs/quasi-static.md, "Stress-free sand"); IGS 1 stopped at
// 0.6 D until the sand model cut a tensile principal stress off instead of sending the whole
// stress to the floor ("Tension cut-off"). About 100 s for both on two cores, hence Long.
TEST(CentrifugeCli, LongIgsCaseFromTheSandSurfaceRunsThroughOnTheQuasiStaticAnalysis) {
  for (const char* set : {"igs1", "igs3"}) {
    SCOPED_TRACE(set);
    const TestDir dir(std::string("centrifuge-cli-") + set);
    const fs::path out = dir.path() / "run";
    const std::string file =
        std::string(PILEMPM_SOURCE_DIR) + "/examples/centrifuge/" + set + "_small.toml";
    const Result r = run_pilempm("centrifuge run '" + file + "' --analysis quasi-static --out '" +
                                 out.string() + "' --quiet --no-plots");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const double D = 11.3;  // [mm]
    const std::string summary = read_text(out / "summary.json");
    EXPECT_NEAR(json_number(summary, "installation_tip_depth_D"), 4.7, 1e-6) << summary;
    EXPECT_LT(json_number(summary, "equilibrium_error"), 0.02) << summary;
    EXPECT_GT(json_number(summary, "installation_head_force_N"), 0.0) << summary;
    const Csv pile = read_csv(out / "pile.csv");
    ASSERT_GT(pile.rows.size(), 10u);
    for (std::size_t k = 0; k < pile.rows.size(); ++k) {
      const double head = pile.number(k, "head_force_N");
      EXPECT_NEAR(head, pile.number(k, "tip_force_N") + pile.number(k, "shaft_force_N"),
                  1e-3 * std::abs(head) + 1e-3)
          << "row " << k;
    }
    // No particle inside the pile at the end (as in the quick case's test: half a cell allowed).
    const Csv fields = read_csv(out / "fields_installation.csv");
    ASSERT_EQ(fields.rows.size(), static_cast<std::size_t>(json_number(summary, "particles")));
    std::size_t inside = 0;
    for (std::size_t k = 0; k < fields.rows.size(); ++k)
      if (inside_pile(fields.number(k, "r_mm"), fields.number(k, "depth_mm"), 4.7 * D,
                      0.5 * D / 4.0))
        ++inside;
    EXPECT_EQ(inside, 0u);
  }
}

}  // namespace
