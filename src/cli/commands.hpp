#pragma once
// Registration of the subcommands. Each command file adds its subcommands to the app; a
// subcommand does its work in its CLI11 callback and reports failures by throwing pilempm::Error.
#include <CLI/CLI.hpp>

#include <optional>
#include <stdexcept>
#include <string>

#include "pilempm/io/output/output_folder.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::cli {

/// The exit statuses of pilempm (README.md, `pilempm --help`).
inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 2;          ///< bad input, a file, a run that stopped
inline constexpr int kExitInternalError = 3;  ///< a bug: an exception pilempm does not know
inline constexpr int kExitChecksFailed = 4;   ///< the run ended, its own checks failed
/// The footer of `pilempm --help` that lists them.
const char* exit_status_help();

/// Thrown by a command whose run ended but failed its own checks, after everything it computed
/// was written and its FAILED lines printed; the message says which checks and where the
/// results are. main() prints it and exits with kExitChecksFailed.
class ChecksFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void register_commands(CLI::App& app);

/// The check of every number on the command line: not empty, a whole number in the text, finite
/// and of a sane magnitude (NumberRange's rule: it is multiplied by units, so 1e306 kPa would be
/// infinite). Chain a range check after it.
const CLI::Validator& sane_number();

/// Adds --overwrite (remove the files of an earlier run in the output folder first) to a
/// command that writes into an output folder.
void add_overwrite_flag(CLI::App& command, bool& overwrite);

/// Adds --analysis (explicit or quasi-static: the analysis of every run whatever its centrifuge
/// case file says) to a command that reads centrifuge case files.
void add_analysis_option(CLI::App& command, std::string& analysis);
/// The analysis --analysis names; none when it was not given ("").
std::optional<simulation::MpmAnalysis> analysis_option(const std::string& name);

/// Takes the output folder of a command's run (claim_output_folder) and says on stderr what it
/// removed: temporary files left by a run that was stopped, an earlier run's files (overwrite).
void take_output_folder(const std::string& directory, const OutputFolderOptions& options);

}  // namespace pilempm::cli
