#pragma once
// Drawing a figures.json with the plotting script tools/plot/plot_figures.py (built into
// pilempm) and a Python interpreter with matplotlib. The interpreter is /usr/bin/python3 by
// default (Debian's python3-matplotlib), then `python3` on PATH; a missing interpreter or
// matplotlib is not an error: the outcome says what was tried, so that the caller can warn and
// tell how to draw the figures later.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

/// The text of tools/plot/plot_figures.py.
std::string_view plot_script_text();

/// What a child process printed (stdout and stderr together) and how it ended.
struct ProcessResult {
  bool started = false;  ///< false: it could not be started (`error` says why)
  int exit_code = -1;    ///< -1 when it did not exit normally
  std::string output;
  std::string error;
};

/// Runs `program` with `arguments` (no shell; a program without '/' is looked up in PATH),
/// passing each line it prints to `line` (may be empty) as it comes.
ProcessResult run_process(const std::string& program, const std::vector<std::string>& arguments,
                          const std::function<void(const std::string&)>& line = {});

struct PlotOutcome {
  bool plotted = false;            ///< every figure was drawn
  std::string python;              ///< the interpreter used ("" when none was usable)
  std::string problem;             ///< why nothing or not everything was drawn ("" when plotted)
  std::vector<std::string> tried;  ///< "interpreter: what happened", for the warning
};

/// Draws `figures_json` with `script`. `python`: the interpreter to use; "" = the default
/// search above. Each line the script prints goes to `progress`.
PlotOutcome draw_figures(const std::filesystem::path& script,
                         const std::filesystem::path& figures_json, const std::string& python,
                         const std::function<void(const std::string&)>& progress = {});

}  // namespace pilempm
