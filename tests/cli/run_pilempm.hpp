#pragma once
// Running the built pilempm program from a test (PILEMPM_BINARY is its path).
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "../support/files.hpp"

namespace pilempm_test {

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

/// Runs a shell command line and collects its output (stdout and stderr together) and exit code.
inline Result run_shell(const std::string& command) {
  Result r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Runs `pilempm ARGUMENTS` through the shell and collects its output and exit code. With
/// `timeout_s` > 0 the program is stopped after that many seconds (killed 10 s later if need be)
/// and the exit code is then 124. `shell_prefix` runs in the shell before it (e.g. a ulimit).
inline Result run_pilempm(const std::string& arguments, int timeout_s = 0,
                          const std::string& shell_prefix = "") {
  const std::string limit =
      timeout_s > 0 ? "timeout -k 10 " + std::to_string(timeout_s) + " " : std::string();
  return run_shell(shell_prefix + limit + std::string("'") + PILEMPM_BINARY + "' " + arguments);
}

using pilempm::test_support::read_text;

}  // namespace pilempm_test
