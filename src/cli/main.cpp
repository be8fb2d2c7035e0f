// The pilempm command: parses the command line and hands each subcommand to the library.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"

namespace {

// OpenMP threads that reach a loop's end first spin while they wait for the others; by default
// libgomp spins for 300 000 rounds before it sleeps, so beside another busy process the spinning
// threads take the cores the late thread needs. A short spin (10 000 rounds, some microseconds)
// keeps the quick hand-over of a quiet machine and gives the core up soon under load. libgomp
// reads its settings before main, so the program sets the variable and starts itself again;
// a user's own OMP_WAIT_POLICY or GOMP_SPINCOUNT is left as it is.
void use_short_openmp_spin_waits(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr)
    return;
  if (::setenv("GOMP_SPINCOUNT", "10000", 0) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only when it failed: go on with the defaults
}

}  // namespace

int main(int argc, char** argv) {
  use_short_openmp_spin_waits(argv);
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
