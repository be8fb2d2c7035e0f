#include "cli/commands.hpp"

namespace pilempm::cli {

// Defined in the command files of this folder, one per group of subcommands.
void register_analytic_commands(CLI::App& app);    // analytic_commands.cpp
void register_calibrate_commands(CLI::App& app);   // calibrate_commands.cpp
void register_centrifuge_commands(CLI::App& app);  // centrifuge_commands.cpp
void register_element_commands(CLI::App& app);     // element_commands.cpp
void register_mpm_commands(CLI::App& app);         // mpm_commands.cpp
void register_study_commands(CLI::App& app);       // study_commands.cpp

void register_commands(CLI::App& app) {
  register_analytic_commands(app);
  register_element_commands(app);
  register_centrifuge_commands(app);
  register_mpm_commands(app);
  register_study_commands(app);
  register_calibrate_commands(app);
}

}  // namespace pilempm::cli
