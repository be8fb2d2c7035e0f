#pragma once
// The centrifuge study's reference data set (docs/data/README.md): for each finished run of a
// study folder, its case file and its curves (the pile's head, tip and shaft force and tip stress
// against travel, through installation, relaxation and load test) as plain CSV, and a README.md
// that says what each run is (analysis, mesh, load step) and its headline numbers, so that other
// codes can compare against them without pilempm.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm {

/// One run of the set: its case file in the study (DIR/<stem>/, whose case.toml is the case
/// as it ran) and the labels it has in the study's groups.
struct ReferenceDataRun {
  std::string file;                 ///< e.g. "md_original.toml"
  std::vector<std::string> labels;  ///< e.g. {"medium dense, original", "MPM-2 ..."}
  int failed_checks = 0;            ///< of the run's own checks, as the study judges them
};

struct ReferenceDataReport {
  std::vector<std::string> written;  ///< the case files whose data were written
  std::vector<std::string> missing;  ///< the case files without a finished run (no summary.csv)
  std::filesystem::path readme;
};

/// The last part of a folder's path ("runs/ref/" gives "ref"): how README.md names the study
/// folder, without the machine's paths.
std::string reference_folder_name(const std::filesystem::path& dir);

/// The columns of pile.csv that the set keeps, in its order (those of the explicit analysis's
/// dynamics, kinetic energy, momentum and damping, are left out).
const std::vector<std::string>& reference_data_columns();

/// Writes into `data_dir` (which must exist; files are replaced atomically) <stem>.toml (the
/// case file as the run read it, DIR/<stem>/case.toml), <stem>.csv and README.md, for the runs
/// of `study_dir` that finished (their summary.csv and pile.csv exist). `analysis`: the analysis
/// the study gave every run (`--analysis`; the case files' own where none), which README.md and
/// a comment atop each case file state; `command`: the study's command, which README.md quotes.
/// Throws Error naming the file and line when a case file, pile.csv or summary.csv cannot be read
/// or lacks a column.
ReferenceDataReport write_centrifuge_reference_data(
    const std::filesystem::path& study_dir, const std::vector<ReferenceDataRun>& runs,
    const std::filesystem::path& data_dir,
    std::optional<simulation::MpmAnalysis> analysis = std::nullopt,
    const std::string& command = "");

}  // namespace pilempm
