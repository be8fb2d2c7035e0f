// `pilempm study centrifuge --jobs N` and `--write-commands FILE` run as a user runs them: the
// runs of a group as child processes, two at once, give the CSV files of the serial study byte
// for byte (but the wall time); a run that fails is named with its exit code and its log while
// the others finish; the command list run by GNU parallel (and one line of it as a Slurm array
// task runs it), then --report-only, gives the serial study's report. The cases are four tiny
// ones (about a second each) under the names of the `igs` group's case files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_pilempm.hpp"

namespace {

using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;
using pilempm_test::run_shell;

namespace fs = std::filesystem;

const std::vector<std::string> kCases{"igs1_small", "igs2_small", "igs3_small", "igs4_small"};

// Four tiny cases (R = 4 D, H = 6 D, D/2 cells, 0.5 D of installation, no relaxation or load
// test; under 200 particles, so one thread whatever the machine) that differ in e0.
void write_tiny_cases(const fs::path& dir) {
  fs::create_directories(dir);
  const char* e0[] = {"0.64", "0.68", "0.71", "0.75"};
  for (std::size_t k = 0; k < kCases.size(); ++k)
    std::ofstream(dir / (kCases[k] + ".toml"))
        << "title = \"tiny " << kCases[k] << "\"\n\n[test]\ncontainer_radius_D = 4.0\n"
        << "sand_height_D = 6.0\n\n[sand]\nmaterial = \"original\"\ne0 = " << e0[k]
        << "\ne0_at = \"initial-stress\"\n\n[installation]\nwished_in_place_D = 2.0\n"
        << "depth_D = 0.5\n\n[relaxation]\nenabled = false\n\n[load_test]\ndisplacement_D = 0.0\n"
        << "\n[mesh]\ncells_per_D = 2\nfine_radius_D = 2.0\nfine_depth_below_tip_D = 2.0\n"
        << "headroom_D = 1.0\n";
}

std::string quoted(const fs::path& path) {
  return "'" + path.string() + "'";
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, separator);) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.emplace_back();
  return fields;
}

std::string join(const std::vector<std::string>& fields, char separator) {
  std::string line;
  for (std::size_t k = 0; k < fields.size(); ++k)
    line += (k == 0 ? "" : std::string(1, separator)) + fields[k];
  return line;
}

// `text` (CSV, or Markdown tables) with the cells below the header cell `name` blanked: the wall
// time, the only thing that differs between two runs of a case. Fails the test when no line has
// that header.
std::string without_column(const std::string& text, char separator, const std::string& name) {
  std::istringstream in(text);
  std::string line, out;
  std::size_t column = std::string::npos;
  while (std::getline(in, line)) {
    std::vector<std::string> fields = split(line, separator);
    const auto header = std::find(fields.begin(), fields.end(), name);
    if (header != fields.end())
      column = static_cast<std::size_t>(header - fields.begin());
    else if (column < fields.size())
      fields[column] = "(wall time)";
    out += join(fields, separator) + "\n";
  }
  EXPECT_NE(column, std::string::npos) << "no column " << name << " in\n" << text;
  return out;
}

std::string without_wall_time(const std::string& summary_csv) {
  return without_column(summary_csv, ',', "wall_time_s");
}

// A quasi-static run's load_steps.csv without its timings (the rest is the Newton work).
std::string without_load_step_times(const std::string& load_steps_csv) {
  std::string text = load_steps_csv;
  for (const char* column : {"material_s", "assembly_s", "factorisation_s", "wall_s"})
    text = without_column(text, ',', column);
  return text;
}

std::string readme_without_wall_time(const std::string& readme) {
  return without_column(readme, '|', " wall time [s] ");
}

// Every CSV file of the study's case folders (their path in the study folder: content), and
// figures.json when all cases are asked for (a group with runs missing draws fewer);
// summary.csv and a quasi-static run's load_steps.csv without their times.
std::map<std::string, std::string> study_results(const fs::path& study,
                                                 const std::vector<std::string>& cases = kCases) {
  std::map<std::string, std::string> files;
  for (const std::string& c : cases) {
    if (!fs::exists(study / c)) continue;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(study / c)) {
      if (e.path().extension() != ".csv") continue;
      const std::string name = e.path().lexically_relative(study).generic_string();
      const std::string text = read_text(e.path());
      files[name] = e.path().filename() == "summary.csv"      ? without_wall_time(text)
                    : e.path().filename() == "load_steps.csv" ? without_load_step_times(text)
                                                              : text;
    }
  }
  if (cases.size() == kCases.size()) files["figures.json"] = read_text(study / "figures.json");
  return files;
}

// The results of `cases` in `study` equal those of the serial study, file by file.
void expect_serial_results(const fs::path& study, const fs::path& serial,
                           const std::vector<std::string>& cases = kCases) {
  const std::map<std::string, std::string> expected = study_results(serial, cases);
  const std::map<std::string, std::string> got = study_results(study, cases);
  // Each case: pile.csv, summary.csv, fields_installation.csv, mpm/energies.csv, mpm/bodies.csv.
  EXPECT_GE(expected.size(), 5 * cases.size());
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [name, text] : expected) {
    const auto it = got.find(name);
    ASSERT_NE(it, got.end()) << name;
    EXPECT_TRUE(it->second == text) << name << " differs from the serial run's";
  }
}

class CentrifugeStudyJobsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("pilempm-study-jobs-" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    write_tiny_cases(*dir_ / "cases");
    // The serial study, one thread per run as the child runs have (tiny cases run on one thread
    // anyway: OMP_NUM_THREADS=1 makes sure).
    serial_ = new Result(
        run_pilempm(study_flags() + " --out " + quoted(serial()), 600, "OMP_NUM_THREADS=1 "));
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(*dir_, ec);
    delete serial_;
    delete dir_;
  }
  void SetUp() override { ASSERT_EQ(serial_->exit_code, 0) << serial_->output; }
  static std::string study_flags() {
    return "study centrifuge --groups igs --no-plots --cases " + quoted(*dir_ / "cases");
  }
  static fs::path serial() { return *dir_ / "serial"; }
  static fs::path* dir_;
  static Result* serial_;
};

fs::path* CentrifugeStudyJobsCli::dir_ = nullptr;
Result* CentrifugeStudyJobsCli::serial_ = nullptr;

TEST_F(CentrifugeStudyJobsCli, TwoAtOnceWriteTheSerialResultsByteForByte) {
  const fs::path out = *dir_ / "jobs2";
  const Result r = run_pilempm(study_flags() + " --jobs 2 --out " + quoted(out), 600);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_serial_results(out, serial());
  EXPECT_EQ(readme_without_wall_time(read_text(out / "README.md")),
            readme_without_wall_time(read_text(serial() / "README.md")));
  // A line per run as it ends, with its wall time; each run's output in its log.
  EXPECT_NE(r.output.find("4 runs, 2 at once, each on one thread"), std::string::npos) << r.output;
  for (const std::string& c : kCases) {
    EXPECT_NE(r.output.find("study: " + c + ".toml done in "), std::string::npos) << r.output;
    EXPECT_NE(read_text(out / "logs" / (c + ".log")).find("checks: PASS"), std::string::npos) << c;
  }
  EXPECT_NE(r.output.find("(4/4)"), std::string::npos) << r.output;
}

TEST_F(CentrifugeStudyJobsCli, RunsThatFailAreNamedWithExitCodeAndLogTheOthersFinish) {
  const fs::path out = *dir_ / "failing";
  fs::create_directories(out);
  // A plain file where igs2_small's and igs4_small's folders would go: those runs stop at once.
  std::ofstream(out / "igs2_small") << "in the way\n";
  std::ofstream(out / "igs4_small") << "in the way\n";
  Result r = run_pilempm(study_flags() + " --jobs 2 --out " + quoted(out), 600);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  const std::string log2 = (out / "logs" / "igs2_small.log").string();
  const std::string log4 = (out / "logs" / "igs4_small.log").string();
  EXPECT_NE(r.output.find("igs2_small.toml did not finish: exit code 2"), std::string::npos)
      << r.output;
  // The closing message names both, in the study's order whichever ended first.
  EXPECT_NE(r.output.find("2 runs of the study did not finish: igs2_small.toml (exit code 2, log " +
                          log2 + "), igs4_small.toml (exit code 2, log " + log4 + ")"),
            std::string::npos)
      << r.output;
  EXPECT_NE(read_text(log2).find("output folder"), std::string::npos) << read_text(log2);
  const std::string readme = read_text(out / "README.md");
  EXPECT_NE(readme.find("`igs2_small.toml` | **did not finish**: exit code 2 (log "
                        "`logs/igs2_small.log`)"),
            std::string::npos)
      << readme;
  // The group's figures draw the two runs that finished and name the two that did not: two field
  // panels side by side instead of four, two head-force curves.
  EXPECT_NE(readme.find("its figures draw the 2 of 4 that did"), std::string::npos) << readme;
  const std::string figures = read_text(out / "figures.json");
  for (const char* run : {"igs1_small", "igs3_small"}) {
    EXPECT_NE(figures.find(std::string(run) + "/pile.csv"), std::string::npos) << figures;
    EXPECT_NE(figures.find(std::string(run) + "/fields_installation.csv"), std::string::npos)
        << figures;
  }
  EXPECT_EQ(figures.find("igs2_small/"), std::string::npos) << figures;
  EXPECT_EQ(figures.find("igs4_small/"), std::string::npos) << figures;
  EXPECT_NE(figures.find("\"layout\": [1, 2]"), std::string::npos) << figures;
  EXPECT_NE(figures.find("(without IGS 2, IGS 4: not finished)"), std::string::npos) << figures;
  expect_serial_results(out, serial(), {"igs1_small", "igs3_small"});

  // The way cleared, --resume runs only those two.
  fs::remove(out / "igs2_small");
  fs::remove(out / "igs4_small");
  r = run_pilempm(study_flags() + " --jobs 2 --resume --out " + quoted(out), 600);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("igs1_small.toml done before, kept"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2 runs, 2 at once"), std::string::npos) << r.output;
  expect_serial_results(out, serial());
}

// GNU parallel (Debian's `parallel`), as docs/centrifuge.md uses it. CI installs it through
// scripts/install-deps.sh, so there its absence fails the test; elsewhere (a build without
// install-deps.sh) the test is skipped with a message saying how to install it.
bool gnu_parallel_here(std::string& why) {
  const Result version = run_shell("parallel --version");
  if (version.exit_code == 0 && version.output.find("GNU parallel") != std::string::npos)
    return true;
  why = "GNU parallel is not installed (`parallel --version`: exit code " +
        std::to_string(version.exit_code) + "): apt-get install parallel, or bash " +
        "scripts/install-deps.sh";
  return false;
}

TEST_F(CentrifugeStudyJobsCli, GnuParallelRunsTheCommandListAndReportOnlyGathersIt) {
  std::string why;
  if (!gnu_parallel_here(why)) {
    if (std::getenv("CI") != nullptr) FAIL() << why << " (CI installs it through that script)";
    GTEST_SKIP() << why;
  }
  const fs::path out = *dir_ / "parallel";
  const fs::path commands = *dir_ / "commands.txt";
  Result r = run_pilempm(
      study_flags() + " --out " + quoted(out) + " --write-commands " + quoted(commands), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote 4 commands"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "README.md"));  // nothing ran yet
  r = run_shell("parallel --will-cite -j 2 < " + quoted(commands));
  ASSERT_EQ(r.exit_code, 0) << r.output << read_text(commands);
  r = run_pilempm(study_flags() + " --report-only --out " + quoted(out), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_serial_results(out, serial());
  EXPECT_EQ(readme_without_wall_time(read_text(out / "README.md")),
            readme_without_wall_time(read_text(serial() / "README.md")));
}

TEST_F(CentrifugeStudyJobsCli, ASlurmArrayTaskRunsItsOwnLineOfTheList) {
  const fs::path out = *dir_ / "slurm";
  const fs::path commands = *dir_ / "slurm.txt";
  Result r = run_pilempm(
      study_flags() + " --out " + quoted(out) + " --write-commands " + quoted(commands), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // docs/centrifuge.md's job script line, as task 3 of the array runs it.
  r = run_shell("SLURM_ARRAY_TASK_ID=3 /bin/sh -c 'sed -n \"${SLURM_ARRAY_TASK_ID}p\" " +
                commands.string() + " | bash'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string& c : kCases)
    EXPECT_EQ(fs::exists(out / c / "summary.csv"), c == "igs3_small") << c;
  expect_serial_results(out, serial(), {"igs3_small"});
  r = run_pilempm(study_flags() + " --report-only --out " + quoted(out), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(read_text(out / "README.md").find("`igs1_small.toml` | not run"), std::string::npos);
}

// --analysis quasi-static runs every case of the study on the quasi-static analysis, whatever the
// case files say (they name none: explicit), in this process and as child runs (which get the
// flag: their results equal the serial ones byte for byte), and the command list passes it on.
TEST_F(CentrifugeStudyJobsCli, AnalysisFlagRunsEveryCaseOnItInProcessAndAsChildren) {
  const fs::path serial_qs = *dir_ / "qs-serial";
  const fs::path jobs_qs = *dir_ / "qs-jobs2";
  const std::string flags = study_flags() + " --analysis quasi-static";
  Result r = run_pilempm(flags + " --out " + quoted(serial_qs), 600, "OMP_NUM_THREADS=1 ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("groups igs, every run quasi-static"), std::string::npos) << r.output;
  for (const std::string& c : kCases) {
    EXPECT_NE(read_text(serial_qs / c / "mpm_case.toml").find("analysis = \"quasi-static\""),
              std::string::npos)
        << c;
    EXPECT_EQ(read_text(serial() / c / "mpm_case.toml").find("quasi-static"), std::string::npos)
        << c;
    // Another analysis, another path: the pile's forces differ from the explicit run's.
    EXPECT_NE(read_text(serial_qs / c / "pile.csv"), read_text(serial() / c / "pile.csv")) << c;
  }
  EXPECT_NE(read_text(serial_qs / "README.md").find("Every run: the quasi-static analysis"),
            std::string::npos);
  r = run_pilempm(flags + " --jobs 2 --out " + quoted(jobs_qs), 600);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_serial_results(jobs_qs, serial_qs);
  // Their reference data say which analysis ran, in README.md and atop each case file.
  const fs::path data = *dir_ / "qs-data";
  r = run_pilempm(
      flags + " --report-only --out " + quoted(serial_qs) + " --reference-data " + quoted(data),
      120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string readme = read_text(data / "README.md");
  EXPECT_NE(readme.find("Made by `pilempm study centrifuge --out qs-serial --cases "),
            std::string::npos)
      << readme;
  EXPECT_NE(readme.find(" --groups igs --analysis quasi-static` and then the same with "
                        "`--report-only --reference-data DIR`"),
            std::string::npos)
      << readme;
  for (const std::string& c : kCases) {
    EXPECT_NE(readme.find("`" + c + ".csv` | quasi-static, load step 0.025 D | 2, 2 |"),
              std::string::npos)
        << readme;
    EXPECT_EQ(read_text(data / (c + ".toml")),
              "# Run on the quasi-static analysis (`pilempm centrifuge run " + c +
                  ".toml --analysis quasi-static`), whatever [solver] analysis says below.\n" +
                  read_text(*dir_ / "cases" / (c + ".toml")));
  }

  const fs::path commands = *dir_ / "qs-commands.txt";
  r = run_pilempm(
      flags + " --out " + quoted(*dir_ / "qs-list") + " --write-commands " + quoted(commands), 120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--analysis quasi-static --report-only"), std::string::npos) << r.output;
  std::istringstream in(read_text(commands));
  std::size_t lines = 0;
  for (std::string line; std::getline(in, line); ++lines)
    EXPECT_NE(line.find(" --analysis quasi-static"), std::string::npos) << line;
  EXPECT_EQ(lines, kCases.size());
}

// The command list without running anything: --resume leaves out the finished runs, a folder
// with runs is refused without --resume or --overwrite, every path is absolute.
// The lines of a CSV file but its comments.
std::vector<std::string> data_lines(const fs::path& file) {
  std::vector<std::string> lines;
  std::istringstream in(read_text(file));
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line.front() != '#') lines.push_back(line);
  return lines;
}

// The cells of column `name` of a CSV file, as written.
std::vector<std::string> column_text(const fs::path& file, const std::string& name) {
  const std::vector<std::string> lines = data_lines(file);
  std::vector<std::string> cells;
  if (lines.empty()) return cells;
  const std::vector<std::string> header = split(lines.front(), ',');
  const auto at = std::find(header.begin(), header.end(), name);
  if (at == header.end()) return cells;
  for (std::size_t k = 1; k < lines.size(); ++k)
    cells.push_back(split(lines[k], ',').at(std::size_t(at - header.begin())));
  return cells;
}

TEST_F(CentrifugeStudyJobsCli, ReferenceDataHoldEachFinishedRunsCaseAndCurvesAsWritten) {
  // The serial study without its last run, gathered by --report-only into a data set.
  const fs::path study = *dir_ / "reference_study", data = *dir_ / "reference_data";
  fs::copy(serial(), study, fs::copy_options::recursive);
  fs::remove_all(study / kCases.back());
  fs::create_directories(data);
  std::ofstream(data / "notes.txt") << "a user's own file\n";
  Result r = run_pilempm(
      study_flags() + " --report-only --out " + quoted(study) + " --reference-data " + quoted(data),
      120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("reference data of 3 runs"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not run: " + kCases.back() + ".toml"), std::string::npos) << r.output;
  const std::string readme = read_text(data / "README.md");
  // The columns: pile.csv's but those of the explicit analysis's dynamics.
  std::vector<std::string> columns = split(data_lines(study / kCases[0] / "pile.csv")[0], ',');
  for (const std::string dynamic :
       {"kinetic_J", "pile_work_J", "sand_momentum_rate_N", "damping_force_N"}) {
    const auto at = std::find(columns.begin(), columns.end(), dynamic);
    ASSERT_NE(at, columns.end()) << dynamic;
    columns.erase(at);
  }
  EXPECT_EQ(columns.size(), 14U);
  for (std::size_t k = 0; k + 1 < kCases.size(); ++k) {
    const fs::path csv = data / (kCases[k] + ".csv"), pile = study / kCases[k] / "pile.csv";
    // The case file as the run read it, one row per row of the run's pile.csv, the kept
    // columns' cells exactly as written there.
    EXPECT_EQ(read_text(data / (kCases[k] + ".toml")),
              read_text(*dir_ / "cases" / (kCases[k] + ".toml")));
    const std::vector<std::string> lines = data_lines(csv);
    ASSERT_FALSE(lines.empty()) << csv;
    EXPECT_EQ(lines.front(), join(columns, ','));
    EXPECT_EQ(lines.size(), data_lines(pile).size());
    for (const std::string& name : columns) {
      EXPECT_EQ(column_text(csv, name), column_text(pile, name)) << kCases[k] << " " << name;
      EXPECT_NE(readme.find("`" + name), std::string::npos) << name << " is not described";
    }
    EXPECT_GE(column_text(csv, "head_force_N").size(), 5U);
    // The README's row: the label, the files, the analysis and the head force of summary.csv.
    const std::string label = "| IGS " + std::to_string(k + 1) + " | `" + kCases[k] + ".toml`, `" +
                              kCases[k] + ".csv` | explicit, jacking at 0.025 m/s | 2, 2 |";
    EXPECT_NE(readme.find(label), std::string::npos) << label << "\n" << readme;
  }
  EXPECT_FALSE(fs::exists(data / (kCases.back() + ".csv")));
  EXPECT_NE(readme.find("| IGS 4 | not run"), std::string::npos) << readme;

  // Gathered again with another run missing: the set is replaced (the first run's files go),
  // the user's own file stays.
  fs::remove_all(study / kCases.front());
  r = run_pilempm(
      study_flags() + " --report-only --out " + quoted(study) + " --reference-data " + quoted(data),
      120);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(data / (kCases.front() + ".csv")));
  EXPECT_FALSE(fs::exists(data / (kCases.front() + ".toml")));
  EXPECT_TRUE(fs::exists(data / (kCases[1] + ".csv")));
  EXPECT_EQ(read_text(data / "notes.txt"), "a user's own file\n");
}

TEST(StudyCommandList, ResumeLeavesOutFinishedRunsAndEveryPathIsAbsolute) {
  const fs::path dir =
      fs::temp_directory_path() / ("pilempm-study-command-list-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  write_tiny_cases(dir / "cases");
  fs::create_directories(dir / "study" / "igs1_small");
  std::ofstream(dir / "study" / "igs1_small" / "summary.csv") << "wall_time_s\n1\n";
  std::ofstream(dir / "study" / "igs1_small" / ".pilempm-files") << "summary.csv\n";  // a run's
  const std::string flags = "study centrifuge --groups igs --cases " + quoted(dir / "cases") +
                            " --out " + quoted(dir / "study") + " --write-commands " +
                            quoted(dir / "commands.txt");
  Result r = run_pilempm(flags, 60);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds the files of another run"), std::string::npos) << r.output;
  r = run_pilempm(flags + " --resume", 60);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote 3 commands"), std::string::npos) << r.output;
  std::istringstream in(read_text(dir / "commands.txt"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::string& line = lines[k];
    const std::string c = kCases[k + 1];
    EXPECT_EQ(line.rfind("OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} /", 0), 0u) << line;
    // Each path as one shell word (in quotes when it needs them).
    EXPECT_NE(line.find(" centrifuge run "), std::string::npos) << line;
    EXPECT_LT(line.find(" centrifuge run "), line.find((dir / "cases" / (c + ".toml")).string()))
        << line;
    EXPECT_LT(line.find((dir / "cases" / (c + ".toml")).string()), line.find(" --out ")) << line;
    EXPECT_LT(line.find(" --out "), line.find((dir / "study" / c).string())) << line;
    EXPECT_NE(line.find(" --overwrite > "), std::string::npos) << line;
    EXPECT_LT(line.find(" --overwrite > "),
              line.find((dir / "study" / "logs" / (c + ".log")).string()))
        << line;
    EXPECT_EQ(line.substr(line.size() - 5), " 2>&1") << line;
  }
  fs::remove_all(dir);
}

// The flags that say how a study runs: a clear error naming the flag and what is allowed, and
// nothing written.
TEST(StudyJobsFlags, BadValuesAndCombinationsAreRefusedNamingTheFlag) {
  const fs::path out =
      fs::temp_directory_path() / ("pilempm-study-jobs-flags-" + std::to_string(::getpid()));
  const std::string study = "study centrifuge --groups igs --no-plots --out " + quoted(out);
  for (const std::string value : {"0", "-1", "1025", "two", "1.5"}) {
    const Result r = run_pilempm(study + " --jobs " + value, 60);
    EXPECT_NE(r.exit_code, 0) << value;
    EXPECT_NE(r.output.find("--jobs: the number of runs at once must be a whole number from 1 to "
                            "1024, not " +
                            value),
              std::string::npos)
        << r.output;
  }
  struct Refused {
    std::string flags, named, other;
  };
  for (const Refused& c : std::vector<Refused>{
           {"--jobs 2 --report-only", "--jobs", "--report-only"},
           {"--write-commands x.txt --report-only", "--write-commands", "--report-only"},
           {"--write-commands x.txt --jobs 2", "--jobs", "--write-commands"},
           {"--write-commands x.txt --reference-data d", "--reference-data", "--write-commands"}}) {
    const Result r = run_pilempm(study + " " + c.flags, 60);
    EXPECT_EQ(r.exit_code, 2) << c.flags << "\n" << r.output;
    EXPECT_NE(r.output.find("pilempm: error: command line: " + c.named), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("not with " + c.other), std::string::npos) << r.output;
  }
  // The reference data set apart from the study's folder.
  for (const fs::path& data : {out, out / "data", out.parent_path()}) {
    const Result r = run_pilempm(study + " --report-only --reference-data " + quoted(data), 60);
    EXPECT_EQ(r.exit_code, 2) << data << "\n" << r.output;
    EXPECT_NE(r.output.find("pilempm: error: command line: --reference-data"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("a folder apart from the study's --out"), std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(out));
  const Result help = run_pilempm("study centrifuge --help");
  EXPECT_NE(help.output.find("--jobs"), std::string::npos);
  EXPECT_NE(help.output.find("--write-commands"), std::string::npos);
}

}  // namespace
