#pragma once
// Runs of a study as child processes, several at once (`pilempm study centrifuge --jobs N`,
// docs/centrifuge.md, "Parallel and cluster runs"): each child's output goes to its own log
// file, at most N run at a time, started in the order given; and the same runs written as shell
// command lines for GNU parallel or a Slurm job array.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pilempm {

/// One child process: `arguments[0]` is the program (a path; no PATH search), its standard
/// output and error go to `log` (created or truncated), its standard input is /dev/null.
struct ChildRun {
  std::string name;  ///< for messages, e.g. the case file
  std::vector<std::string> arguments;
  std::filesystem::path log;
};

/// How a child ended.
struct ChildOutcome {
  bool started = false;       ///< false: it could not be started (`problem` says why)
  int exit_code = -1;         ///< its exit status; -1 when a signal ended it or it did not start
  int signal = 0;             ///< the signal that ended it (0: none)
  double wall_seconds = 0.0;  ///< from its start to its end, as the parent saw it
  std::string problem;        ///< why it did not start
  bool succeeded() const { return started && exit_code == 0; }
  /// "exit code 2", "killed by signal 9 (Killed)" or "not started: <problem>".
  std::string how_it_ended() const;
};

/// Runs `runs` as child processes, at most `jobs` (>= 1) at a time, started in the order of
/// `runs`. `environment` holds NAME=VALUE entries that replace or add to this process's
/// environment in every child. `finished(index, outcome)` is called in this thread as each
/// child ends, in the order they end; the returned outcomes are in the order of `runs`. A child
/// that fails does not stop the others. An exception thrown by `finished` starts no more
/// children and is thrown again once the running ones have ended.
std::vector<ChildOutcome> run_children(
    const std::vector<ChildRun>& runs, int jobs, const std::vector<std::string>& environment,
    const std::function<void(std::size_t, const ChildOutcome&)>& finished = {});

/// `text` as one word of a POSIX shell command line: bare when it holds only characters no
/// shell reads specially, else in single quotes (a quote inside as '\'').
std::string shell_word(const std::string& text);

/// The command line that runs `run` from a shell, its output into its log: the environment
/// assignments `environment` (written as they are: "NAME=${NAME:-1}" keeps a value the
/// shell has), the arguments as shell words, then `> LOG 2>&1`.
std::string shell_command(const ChildRun& run, const std::vector<std::string>& environment);

}  // namespace pilempm
