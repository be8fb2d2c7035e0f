#include "pilempm/study/process_pool.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <map>
#include <utility>

extern char** environ;

namespace pilempm {

namespace {

using Clock = std::chrono::steady_clock;

std::string variable_name(const std::string& entry) {
  return entry.substr(0, entry.find('='));
}

// This process's environment with `changes` (NAME=VALUE) replacing or adding their variables.
std::vector<std::string> child_environment(const std::vector<std::string>& changes) {
  std::vector<std::string> entries;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string entry(*e);
    const std::string name = variable_name(entry);
    if (std::none_of(changes.begin(), changes.end(),
                     [&name](const std::string& c) { return variable_name(c) == name; }))
      entries.push_back(entry);
  }
  entries.insert(entries.end(), changes.begin(), changes.end());
  return entries;
}

// The argv/envp form of `texts`: pointers into them, ended by a null pointer.
std::vector<char*> c_strings(std::vector<std::string>& texts) {
  std::vector<char*> pointers;
  for (std::string& t : texts) pointers.push_back(t.data());
  pointers.push_back(nullptr);
  return pointers;
}

// Starts `run` with its output into its log; returns its process id, or 0 with `problem` set.
pid_t start_child(const ChildRun& run, std::vector<std::string>& environment,
                  std::string& problem) {
  if (run.arguments.empty()) {
    problem = "no program given";
    return 0;
  }
  const int log = ::open(run.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log < 0) {
    problem = fmt::format("cannot write its log {}: {}", run.log.string(), std::strerror(errno));
    return 0;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log, STDERR_FILENO);
  std::vector<std::string> arguments = run.arguments;
  std::vector<char*> argv = c_strings(arguments);
  std::vector<char*> envp = c_strings(environment);
  pid_t pid = 0;
  const int failed = ::posix_spawn(&pid, argv.front(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(log);
  if (failed != 0) {
    problem = fmt::format("cannot run {}: {}", run.arguments.front(), std::strerror(failed));
    return 0;
  }
  return pid;
}

}  // namespace

std::string ChildOutcome::how_it_ended() const {
  if (!started) return "not started: " + problem;
  if (signal != 0) return fmt::format("killed by signal {} ({})", signal, ::strsignal(signal));
  return fmt::format("exit code {}", exit_code);
}

std::vector<ChildOutcome> run_children(
    const std::vector<ChildRun>& runs, int jobs, const std::vector<std::string>& environment,
    const std::function<void(std::size_t, const ChildOutcome&)>& finished) {
  std::vector<ChildOutcome> outcomes(runs.size());
  std::vector<std::string> env = child_environment(environment);
  const std::size_t at_once = static_cast<std::size_t>(std::max(1, jobs));
  std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;
  // After an exception of `finished` no child starts; it is thrown again when those running
  // have ended (none is left behind).
  std::exception_ptr error;
  const auto report = [&](std::size_t k) {
    if (!finished || error) return;
    try {
      finished(k, outcomes[k]);
    } catch (...) {
      error = std::current_exception();
    }
  };
  std::size_t next = 0;
  while ((next < runs.size() && !error) || !running.empty()) {
    while (next < runs.size() && !error && running.size() < at_once) {
      const std::size_t k = next++;
      const Clock::time_point start = Clock::now();
      const pid_t pid = start_child(runs[k], env, outcomes[k].problem);
      if (pid == 0) {
        report(k);
        continue;
      }
      outcomes[k].started = true;
      running.emplace(pid, std::pair{k, start});
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      // No child left to wait for (something else reaped them): their ends are unknown.
      const std::string problem = std::strerror(errno);
      for (const auto& [child, entry] : running) {
        ChildOutcome& o = outcomes[entry.first];
        o.started = false;
        o.problem = "its end was not seen: " + problem;
        report(entry.first);
      }
      running.clear();
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not one of these runs
    const auto [k, start] = it->second;
    running.erase(it);
    ChildOutcome& o = outcomes[k];
    o.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (WIFEXITED(status)) {
      o.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
      o.signal = WTERMSIG(status);
    }
    report(k);
  }
  if (error) std::rethrow_exception(error);
  return outcomes;
}

std::string shell_word(const std::string& text) {
  const bool bare = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           (c != '\0' && std::strchr("_@%+=:,./-", c) != nullptr);
  });
  if (bare) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string shell_command(const ChildRun& run, const std::vector<std::string>& environment) {
  std::string line;
  for (const std::string& assignment : environment) line += assignment + " ";
  for (std::size_t k = 0; k < run.arguments.size(); ++k) {
    if (k > 0) line += ' ';
    line += shell_word(run.arguments[k]);
  }
  line += " > ";
  line += shell_word(run.log.string());
  line += " 2>&1";
  return line;
}

}  // namespace pilempm
