#include "cli/commands.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_range.hpp"

namespace pilempm::cli {

// Defined in the command files of this folder, one per group of subcommands.
void register_analytic_commands(CLI::App& app);    // analytic_commands.cpp
void register_calibrate_commands(CLI::App& app);   // calibrate_commands.cpp
void register_centrifuge_commands(CLI::App& app);  // centrifuge_commands.cpp
void register_element_commands(CLI::App& app);     // element_commands.cpp
void register_mpm_commands(CLI::App& app);         // mpm_commands.cpp
void register_study_commands(CLI::App& app);       // study_commands.cpp

const char* exit_status_help() {
  return "Exit status: 0 done (and, for runs with checks of their own, every check passed); "
         "2 an error: bad input, a file that cannot be read or written, a run that stopped "
         "(the message says where); 3 an internal error (a bug: please report it); 4 FAILED: "
         "the run ended and wrote its results, but failed its own checks (the summary says "
         "which); 100 and above: the command line was not understood (CLI11's codes).";
}

const CLI::Validator& sane_number() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return "an empty value is not allowed: give a number";
        errno = 0;
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end != text.c_str() + text.size() || errno == ERANGE)
          return fmt::format("not a number: {}", message_text(text));
        return NumberRange::any().problem(value);
      },
      "NUMBER");
  return validator;
}

void add_overwrite_flag(CLI::App& command, bool& overwrite) {
  command.add_flag("--overwrite", overwrite,
                   "the output folder may hold an earlier run: remove that run's files first "
                   "(only the files pilempm wrote there; without it such a folder is refused)");
}

void add_analysis_option(CLI::App& command, std::string& analysis) {
  command
      .add_option("--analysis", analysis,
                  "run with this analysis whatever the case file's [solver] analysis says "
                  "(explicit or quasi-static; the keys of the other analysis are then errors)")
      ->check(CLI::IsMember({"explicit", "quasi-static"}))
      ->type_name("ANALYSIS");
}

std::optional<simulation::MpmAnalysis> analysis_option(const std::string& name) {
  if (name.empty()) return std::nullopt;
  return name == "quasi-static" ? simulation::MpmAnalysis::quasi_static
                                : simulation::MpmAnalysis::explicit_dynamic;
}

void take_output_folder(const std::string& directory, const OutputFolderOptions& options) {
  const OutputFolderClaim claim = claim_output_folder(directory, options);
  if (!claim.removed_temporary.empty())
    fmt::print(stderr,
               "pilempm: removed {} temporary file{} left in {} by a run that was stopped "
               "(first: {})\n",
               claim.removed_temporary.size(), claim.removed_temporary.size() == 1 ? "" : "s",
               directory, claim.removed_temporary.front().string());
  if (!claim.removed_files.empty())
    fmt::print(stderr, "pilempm: --overwrite: removed the {} file{} of the earlier run in {}\n",
               claim.removed_files.size(), claim.removed_files.size() == 1 ? "" : "s", directory);
}

void register_commands(CLI::App& app) {
  register_analytic_commands(app);
  register_element_commands(app);
  register_centrifuge_commands(app);
  register_mpm_commands(app);
  register_study_commands(app);
  register_calibrate_commands(app);
}

}  // namespace pilempm::cli
