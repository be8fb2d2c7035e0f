#pragma once
// Registration of the subcommands. Each command file adds its subcommands to the app; a
// subcommand does its work in its CLI11 callback and reports failures by throwing pilempm::Error.
#include <CLI/CLI.hpp>

namespace pilempm::cli {

void register_commands(CLI::App& app);

}  // namespace pilempm::cli
