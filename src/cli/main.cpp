// The pilempm command: parses the command line and hands each subcommand to the library.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"pilempm: Material Point Method and hypoplastic sand toolkit for pile installation"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pilempm 0.1.0");
  pilempm::cli::register_commands(app);
  try {
    app.parse(argc, argv);  // the chosen subcommand runs in its callback
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const pilempm::Error& e) {
    fmt::print(stderr, "pilempm: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "pilempm: internal error: {}\n", e.what());
    return 3;
  }
  return 0;
}
