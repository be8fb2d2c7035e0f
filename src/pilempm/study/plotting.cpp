#include "pilempm/study/plotting.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>

#include "pilempm/io/output/output_folder.hpp"
#include "pilempm/study/plot_figures_script.hpp"

extern char** environ;

namespace pilempm {

namespace {

constexpr int kExitNoMatplotlib = 3;  // plot_figures.py's exit status without matplotlib

// The PNG files the script writes (a figure's "file", a calibration test's "png", relative to the
// JSON file) belong to the run: listed in its folder's list of files (output_folder.hpp).
void note_figure_files(const std::filesystem::path& figures_json) {
  std::ifstream in(figures_json);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  for (const std::string_view key :
       {std::string_view("\"file\": \""), std::string_view("\"png\": \"")})
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
      const std::size_t start = at + key.size();
      const std::size_t end = text.find('"', start);
      if (end == std::string::npos) break;
      note_output_file(figures_json.parent_path() / text.substr(start, end - start));
    }
}

// Closes a file descriptor once.
struct Descriptor {
  int fd = -1;
  ~Descriptor() { reset(); }
  void reset() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

struct SpawnActions {
  posix_spawn_file_actions_t actions;
  SpawnActions() { posix_spawn_file_actions_init(&actions); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
};

}  // namespace

std::string_view plot_script_text() {
  return {reinterpret_cast<const char*>(generated::kPlotFiguresScript),
          sizeof generated::kPlotFiguresScript};
}

ProcessResult run_process(const std::string& program, const std::vector<std::string>& arguments,
                          const std::function<void(const std::string&)>& line) {
  ProcessResult result;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    result.error = std::strerror(errno);
    return result;
  }
  Descriptor read_end{pipe_fds[0]}, write_end{pipe_fds[1]};
  SpawnActions spawn;
  posix_spawn_file_actions_adddup2(&spawn.actions, write_end.fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&spawn.actions, write_end.fd, STDERR_FILENO);
  std::vector<std::string> argv_text = {program};
  argv_text.insert(argv_text.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned =
      program.find('/') == std::string::npos
          ? ::posix_spawnp(&pid, program.c_str(), &spawn.actions, nullptr, argv.data(), environ)
          : ::posix_spawn(&pid, program.c_str(), &spawn.actions, nullptr, argv.data(), environ);
  write_end.reset();  // the child holds its own copy; EOF comes when it exits
  if (spawned != 0) {
    result.error = std::strerror(spawned);
    return result;
  }
  result.started = true;
  std::string pending;
  char buffer[4096];
  while (true) {
    const ssize_t n = ::read(read_end.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    result.output.append(buffer, static_cast<std::size_t>(n));
    pending.append(buffer, static_cast<std::size_t>(n));
    for (std::size_t eol; (eol = pending.find('\n')) != std::string::npos;) {
      if (line) line(pending.substr(0, eol));
      pending.erase(0, eol + 1);
    }
  }
  if (!pending.empty() && line) line(pending);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      result.error = std::strerror(errno);
      return result;
    }
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (!WIFEXITED(status))
    result.error = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                       : std::string("did not exit normally");
  return result;
}

PlotOutcome draw_figures(const std::filesystem::path& script,
                         const std::filesystem::path& figures_json, const std::string& python,
                         const std::function<void(const std::string&)>& progress) {
  PlotOutcome outcome;
  note_figure_files(figures_json);
  const std::vector<std::string> candidates =
      python.empty() ? std::vector<std::string>{"/usr/bin/python3", "python3"}
                     : std::vector<std::string>{python};
  for (const std::string& candidate : candidates) {
    const ProcessResult check = run_process(candidate, {script.string(), "--check"});
    if (!check.started) {
      outcome.tried.push_back(fmt::format("{}: cannot run it ({})", candidate, check.error));
      continue;
    }
    if (check.exit_code != 0) {
      outcome.tried.push_back(
          fmt::format("{}: {}", candidate,
                      check.exit_code == kExitNoMatplotlib
                          ? std::string("matplotlib is not installed for it")
                          : fmt::format("the script's check failed (exit status {}): {}",
                                        check.exit_code, check.output)));
      continue;
    }
    outcome.python = candidate;
    break;
  }
  if (outcome.python.empty()) {
    outcome.problem = "no Python interpreter with matplotlib";
    return outcome;
  }
  const ProcessResult run =
      run_process(outcome.python, {script.string(), figures_json.string()}, progress);
  if (!run.started) {
    outcome.problem = fmt::format("cannot run {}: {}", outcome.python, run.error);
  } else if (run.exit_code != 0) {
    outcome.problem =
        fmt::format("{} {} failed (exit status {}){}", outcome.python, script.string(),
                    run.exit_code, run.error.empty() ? "" : ": " + run.error);
  } else {
    outcome.plotted = true;
  }
  return outcome;
}

}  // namespace pilempm
