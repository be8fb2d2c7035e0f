#pragma once
// Running the built pilempm program from a test (PILEMPM_BINARY is its path).
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pilempm_test {

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

/// Runs `pilempm ARGUMENTS` through the shell and collects its output and exit code.
inline Result run_pilempm(const std::string& arguments) {
  const std::string command = std::string("'") + PILEMPM_BINARY + "' " + arguments + " 2>&1";
  Result r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The whole text of a file ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace pilempm_test
