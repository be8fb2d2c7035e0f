// The pilempm command: parses the command line and hands each subcommand to the library.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/output/output_folder.hpp"

namespace {

// OpenMP threads that reach a loop's end first spin while they wait for the others; by default
// libgomp spins for 300 000 rounds before it sleeps, so beside another busy process the spinning
// threads take the cores the late thread needs. A short spin (10 000 rounds, some microseconds)
// keeps the quick hand-over of a quiet machine and gives the core up soon under load. libgomp
// reads its settings before main, so the program sets the variable and starts itself again;
// a user's own OMP_WAIT_POLICY or GOMP_SPINCOUNT is left as it is.
void use_short_openmp_spin_waits(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (::setenv("GOMP_SPINCOUNT", "10000", 0) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only when it failed: go on with the defaults
}

// An empty argument ("", or --flag= with nothing after it) is never a value pilempm takes: a
// number would be read as 0 and a name as the default. It is an error naming the option.
void reject_empty_arguments(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument = argv[i];
    const bool empty_inline = argument.starts_with("--") && argument.ends_with("=");
    if (!argument.empty() && !empty_inline) continue;
    const std::string option = empty_inline ? std::string(argument.substr(0, argument.size() - 1))
                               : i > 1 && std::string_view(argv[i - 1]).starts_with("-")
                                   ? std::string(argv[i - 1])
                                   : fmt::format("argument {}", i);
    throw pilempm::InputError("command line", 0, option, "\"\"", "an empty value is not allowed");
  }
}

// However a command ends, with an error too, no temporary file of this process stays behind in
// its output folder.
struct RemoveOwnTemporaryFiles {
  RemoveOwnTemporaryFiles() = default;
  RemoveOwnTemporaryFiles(const RemoveOwnTemporaryFiles&) = delete;
  RemoveOwnTemporaryFiles& operator=(const RemoveOwnTemporaryFiles&) = delete;
  ~RemoveOwnTemporaryFiles() {
    try {
      pilempm::remove_own_temporary_files();
    } catch (...) {  // a destructor does not throw; nothing more to do at the end
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  use_short_openmp_spin_waits(argv);
  CLI::App app{"pilempm: Material Point Method and hypoplastic sand toolkit for pile installation"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pilempm 0.1.0");
  pilempm::cli::register_commands(app);
  app.footer(pilempm::cli::exit_status_help());
  const RemoveOwnTemporaryFiles cleanup;
  try {
    reject_empty_arguments(argc, argv);
    app.parse(argc, argv);  // the chosen subcommand runs in its callback
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // CLI11's own message, with what the user typed escaped (no raw control characters).
    fmt::print(stderr, "pilempm: error: command line: {}\nRun with --help for more information.\n",
               pilempm::message_text(e.what(), 400));
    return e.get_exit_code();
  } catch (const pilempm::cli::ChecksFailed& e) {
    fmt::print(stderr, "pilempm: FAILED: {}\n", e.what());
    return pilempm::cli::kExitChecksFailed;
  } catch (const pilempm::Error& e) {
    fmt::print(stderr, "pilempm: error: {}\n", e.what());
    return pilempm::cli::kExitError;
  } catch (const std::exception& e) {
    fmt::print(stderr, "pilempm: internal error: {}\n", e.what());
    return pilempm::cli::kExitInternalError;
  }
  return pilempm::cli::kExitOk;
}
