#include "pilempm/study/reference_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <sstream>

#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/study/centrifuge_run.hpp"
#include "pilempm/study/csv_table.hpp"

namespace pilempm {

namespace {

std::string stem_of(const std::string& file) {
  return std::filesystem::path(file).stem().string();
}

// The kept columns of a run's pile.csv (the whole file, a centrifuge run writes a few hundred
// rows), each row's cells as written there (no rounding).
std::string curves_csv(const std::filesystem::path& pile_csv) {
  std::istringstream in(read_csv_text(pile_csv));
  std::vector<std::size_t> take;
  std::string out =
      "# pilempm reference data: the pile's forces against travel (columns: docs/data/README.md "
      "or the README.md beside this file)\n";
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (take.empty()) {  // the header
      for (const std::string& name : reference_data_columns()) {
        const auto it = std::find(cells.begin(), cells.end(), name);
        if (it == cells.end())
          throw Error(fmt::format("{}:{}: no column `{}` (a pile.csv of a centrifuge run has it)",
                                  pile_csv.string(), number, name));
        take.push_back(std::size_t(it - cells.begin()));
      }
    }
    for (std::size_t k = 0; k < take.size(); ++k) {
      if (take[k] >= cells.size())
        throw Error(fmt::format("{}:{}: {} cells, column `{}` is the {}th", pile_csv.string(),
                                number, cells.size(), reference_data_columns()[k], take[k] + 1));
      out += (k == 0 ? "" : ",") + cells[take[k]];
    }
    out += '\n';
  }
  if (take.empty()) throw Error(fmt::format("{}: no header line", pile_csv.string()));
  return out;
}

std::string analysis_words(const scenario::CentrifugeScenario& s) {
  if (s.analysis == simulation::MpmAnalysis::quasi_static)
    return fmt::format("quasi-static, load step {:g} D", s.displacement_step_D);
  return fmt::format("explicit, jacking at {:g} m/s", s.jacking.velocity);
}

std::string utc_date() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &utc);
  return text;
}

}  // namespace

std::string reference_folder_name(const std::filesystem::path& dir) {
  std::filesystem::path name = dir.lexically_normal();
  if (name.filename().empty()) name = name.parent_path();  // "runs/ref/"
  return name.filename().string();
}

const std::vector<std::string>& reference_data_columns() {
  static const std::vector<std::string> columns = [] {
    const std::vector<std::string> dynamic{"kinetic_J", "pile_work_J", "sand_momentum_rate_N",
                                           "damping_force_N"};
    std::vector<std::string> kept;
    for (const std::string& c : centrifuge_pile_columns())
      if (std::find(dynamic.begin(), dynamic.end(), c) == dynamic.end()) kept.push_back(c);
    return kept;
  }();
  return columns;
}

ReferenceDataReport write_centrifuge_reference_data(const std::filesystem::path& study_dir,
                                                    const std::vector<ReferenceDataRun>& runs,
                                                    const std::filesystem::path& data_dir,
                                                    std::optional<simulation::MpmAnalysis> analysis,
                                                    const std::string& command) {
  ReferenceDataReport report;
  std::optional<scenario::CentrifugeScenario> first;  // the test's size from the first run
  std::string table =
      "| run | files | analysis | mesh: cells per D, particles per cell (fine zone) | "
      "particles | load or time steps | head force at the end of installation [N] (tip depth "
      "[D]) | peak tip stress [MPa] | load-test capacity [N] (at [mm]) | head-force scatter over "
      "the last D [%] | the run's checks |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ReferenceDataRun& run : runs) {
    const std::string stem = stem_of(run.file);
    const std::filesystem::path dir = study_dir / stem;
    std::string labels;
    for (const std::string& l : run.labels) labels += (labels.empty() ? "" : "; ") + l;
    if (!std::filesystem::exists(dir / "summary.csv") ||
        !std::filesystem::exists(dir / "pile.csv")) {
      report.missing.push_back(run.file);
      table +=
          fmt::format("| {} | not run (no `{}/summary.csv`) | | | | | | | | | |\n", labels, stem);
      continue;
    }
    const NumericTable summary = read_numeric_csv(dir / "summary.csv");
    const std::string case_text = read_case_text(dir / "case.toml");
    const scenario::CentrifugeScenario s =
        read_centrifuge_case_text(case_text, (dir / "case.toml").string(), analysis);
    if (!first) first = s;
    write_file_atomically(data_dir / (stem + ".csv"), curves_csv(dir / "pile.csv"));
    write_file_atomically(
        data_dir / (stem + ".toml"),
        (analysis ? fmt::format("# Run on the {} analysis (`pilempm centrifuge run {}.toml "
                                "--analysis {}`), whatever [solver] analysis says below.\n",
                                to_string(*analysis), stem, to_string(*analysis))
                  : std::string()) +
            case_text);
    table += fmt::format(
        "| {} | `{}.toml`, `{}.csv` | {} | {:g}, {} | {} | {} | {} ({}) | {} | {} ({}) | {} | {} "
        "|\n",
        labels, stem, stem, analysis_words(s), s.cells_per_D, s.particles_per_cell,
        table_cell(summary, "particles", "{:.0f}"), table_cell(summary, "steps", "{:.0f}"),
        table_cell(summary, "installation_head_force_N", "{:.1f}"),
        table_cell(summary, "installation_tip_depth_D", "{:.2f}"),
        table_cell(summary, "peak_tip_stress_MPa", "{:.2f}"),
        table_cell(summary, "load_test_capacity_N", "{:.1f}"),
        table_cell(summary, "load_test_displacement_mm", "{:.3g}"),
        table_cell(summary, "scatter_last_D", "{:.2f}", 100.0),
        run.failed_checks > 0 ? fmt::format("**FAILED** {}", run.failed_checks)
                              : std::string("PASS"));
    report.written.push_back(run.file);
  }

  std::string readme = fmt::format(
      "# Reference data: a displacement pile jacked into sand in a centrifuge, simulated by "
      "pilempm\n\n"
      "Written by pilempm on {} from the study folder `{}`. For each run: `<case>.toml`, the "
      "centrifuge case file it ran (its keys: pilempm's docs/centrifuge.md), and `<case>.csv`, "
      "the forces of the sand on the pile against its travel through installation, relaxation "
      "and load test. The test (docs/study.md): a pile of diameter D = {:g} mm with a 60° cone "
      "jacked at {:g} g into sand in a cylindrical container, axisymmetric; forces are of the "
      "full pile at model scale.\n\n",
      utc_date(), reference_folder_name(study_dir),
      1000.0 * (first ? first->pile_diameter : scenario::CentrifugeScenario{}.pile_diameter),
      first ? first->g_level : scenario::CentrifugeScenario{}.g_level);
  if (!command.empty())
    readme += fmt::format(
        "Made by `{}` and then the same with `--report-only --reference-data "
        "DIR`.\n\n",
        command);
  readme +=
      "These are results at the mesh and load step (or jacking speed) given for each run below; "
      "how much they move with either is in pilempm's docs/verification.md §8.\n\n";
  readme +=
      "## The columns of `<case>.csv`\n\n"
      "| column | unit | what |\n|---|---|---|\n"
      "| `time_s` | s | time; pseudo-time in the quasi-static analysis (one unit a phase's "
      "duration, nothing depends on it) |\n"
      "| `phase` | – | initial-stress (the K0 stress at N g), installation, relaxation (pulled "
      "back until the head force is zero), load-test |\n"
      "| `pile_displacement_mm` | mm | the pile's travel since it was wished in place, down "
      "positive |\n"
      "| `phase_displacement_mm`, `phase_displacement_D` | mm, D | its travel since the phase "
      "began |\n"
      "| `tip_depth_mm`, `tip_depth_D` | mm, D | the depth of the cone's apex below the sand "
      "surface |\n"
      "| `head_force_N` | N | the force of the sand on the whole pile, up positive (= "
      "`tip_force_N` + `shaft_force_N`) |\n"
      "| `tip_force_N`, `shaft_force_N` | N | on the cone and on the shaft |\n"
      "| `tip_stress_MPa` | MPa | the tip force over the pile's section π D²/4 |\n"
      "| `base_reaction_N`, `soil_weight_N`, `equilibrium_residual_N` | N | the container's "
      "vertical reaction on the sand, the sand's weight at N g and head − (reaction − weight): "
      "the global balance, zero to the solver's tolerance in the quasi-static analysis |\n\n"
      "## The runs\n\n";
  readme += table;
  readme +=
      "\nThe head force at the end of installation is the mean over the last cell of travel; the "
      "capacity is the head force at the end of the load test; the scatter is the standard "
      "deviation of the head force about a quadratic over the last D of travel, over its mean "
      "(pilempm's docs/verification.md §8).\n";
  report.readme = data_dir / "README.md";
  write_file_atomically(report.readme, readme);
  return report;
}

}  // namespace pilempm
