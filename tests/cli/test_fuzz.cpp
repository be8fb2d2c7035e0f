// A seeded mutation fuzzer over the example case files of every kind (element tests, MPM cases,
// centrifuge cases) and over the command line. Each mutated input runs in a child process with a
// time limit; the test asserts that no input kills the program with a signal, none hangs, none
// ends in an error that is not one of pilempm's own, and that every rejected case file's message
// names the file (every rejected command line's the option that was changed).
//
// The default suite runs a small budget (FuzzCaseFiles.*, FuzzCommandLine.*); the tests named
// Long run forty times as many inputs. PILEMPM_FUZZ_SEED changes the seed; a failing input is
// kept in the temporary folder and its path printed.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../support/files.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;

// A 64-bit linear congruential generator (Knuth's MMIX constants): the same inputs on every
// machine for a seed.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed * 2862933555777941757ULL + 3037000493ULL) {}
  std::uint64_t next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return state_ >> 17;
  }
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }
  template <class T>
  const T& pick(const std::vector<T>& items) {
    return items[below(items.size())];
  }

 private:
  std::uint64_t state_;
};

std::uint64_t base_seed() {
  const char* text = std::getenv("PILEMPM_FUZZ_SEED");
  return text != nullptr ? std::strtoull(text, nullptr, 10) : 20261203ULL;
}

using test_support::read_text;

// Values that have broken programs before: extremes, non-numbers, empty and long text, control
// characters, broken UTF-8, deep nesting.
const std::vector<std::string>& awkward_values() {
  static const std::vector<std::string> values = {"0",
                                                  "-0.0",
                                                  "-1",
                                                  "1",
                                                  "1e300",
                                                  "-1e300",
                                                  "1e306",
                                                  "5e-324",
                                                  "1e-300",
                                                  "nan",
                                                  "inf",
                                                  "-inf",
                                                  "9223372036854775807",
                                                  "-9223372036854775808",
                                                  "2147483648",
                                                  "4294967297",
                                                  "0.5",
                                                  "1e-12",
                                                  "true",
                                                  "\"\"",
                                                  "\"x\"",
                                                  "[]",
                                                  "[1, 2]",
                                                  "{}",
                                                  "\"\\u001b[31mred\"",
                                                  "\"" + std::string(300, 'a') + "\"",
                                                  "\"\xC3\xA9\xE2\x82\xAC\"",
                                                  "'\xFF\xFE'",
                                                  "1979-05-27T07:32:00Z",
                                                  "[[[[[[[[1]]]]]]]]",
                                                  "\"" + std::string(70, '\x01') + "\""};
  return values;
}

// One mutation of a case file's text.
std::string mutate_text(std::string text, Random& random) {
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) lines.push_back(line);
  }
  const auto join = [&lines]() {
    std::string out;
    for (const auto& line : lines) out += line + "\n";
    return out;
  };
  const auto value_line = [&]() -> std::size_t {  // a line "key = value", or lines.size()
    for (int tries = 0; tries < 20 && !lines.empty(); ++tries) {
      const std::size_t i = random.below(lines.size());
      const auto eq = lines[i].find('=');
      if (eq != std::string::npos && lines[i].find('#') > eq && lines[i][0] != '[') return i;
    }
    return lines.size();
  };
  switch (random.below(12)) {
    case 0:
    case 1:
    case 2: {  // a value replaced by an awkward one (the most useful mutation: weighted)
      const std::size_t i = value_line();
      if (i == lines.size()) break;
      lines[i] = lines[i].substr(0, lines[i].find('=') + 1) + " " + random.pick(awkward_values());
      return join();
    }
    case 3: {  // a number scaled by a power of ten
      const std::size_t i = value_line();
      if (i == lines.size()) break;
      lines[i] += "e" + std::to_string(static_cast<int>(random.below(40)) - 20);
      return join();
    }
    case 4:  // a line removed
      if (!lines.empty())
        lines.erase(lines.begin() + static_cast<long>(random.below(lines.size())));
      return join();
    case 5: {  // a line repeated somewhere else
      if (lines.empty()) break;
      const std::string line = lines[random.below(lines.size())];
      lines.insert(lines.begin() + static_cast<long>(random.below(lines.size() + 1)), line);
      return join();
    }
    case 6: {  // a key misspelt
      const std::size_t i = value_line();
      if (i == lines.size() || lines[i].find('=') < 2) break;
      const std::size_t at = random.below(lines[i].find('=') - 1);
      std::swap(lines[i][at], lines[i][at + 1]);
      return join();
    }
    case 7: {  // one byte changed
      if (text.empty()) break;
      const std::size_t at = random.below(text.size());
      text[at] = static_cast<char>(random.below(256));
      return text;
    }
    case 8:  // cut short
      return text.substr(0, random.below(text.size() + 1));
    case 9: {  // deep nesting or a very long key
      const int depth = 1 + static_cast<int>(random.below(20000));
      std::string key = "x";
      for (int k = 1; k < depth; ++k) key += ".x";
      const std::string line = random.below(2) == 0 ? key + " = 1" : "[" + key + "]";
      lines.insert(lines.begin() + static_cast<long>(random.below(lines.size() + 1)), line);
      return join();
    }
    case 10: {  // a table header repeated (a second [[phase]], [[region]], [solver], ...)
      std::vector<std::size_t> headers;
      for (std::size_t i = 0; i < lines.size(); ++i)
        if (!lines[i].empty() && lines[i][0] == '[') headers.push_back(i);
      if (headers.empty()) break;
      const std::size_t from = random.pick(headers);
      std::size_t to = from + 1;
      while (to < lines.size() && (lines[to].empty() || lines[to][0] != '[')) ++to;
      std::vector<std::string> block(lines.begin() + static_cast<long>(from),
                                     lines.begin() + static_cast<long>(to));
      lines.insert(lines.end(), block.begin(), block.end());
      return join();
    }
    default: {  // an unknown key
      lines.insert(lines.begin() + static_cast<long>(random.below(lines.size() + 1)),
                   "unknown_key_" + std::to_string(random.below(100)) + " = 1");
      return join();
    }
  }
  return text + "\n" + random.pick(awkward_values()) + "\n";
}

// What a child process made of one input.
struct Outcome {
  enum Kind { accepted, rejected, foreign_error, signalled, hung } kind = accepted;
  int signal = 0;
  std::string message;
};

const char* kind_name(Outcome::Kind kind) {
  switch (kind) {
    case Outcome::accepted:
      return "accepted";
    case Outcome::rejected:
      return "rejected";
    case Outcome::foreign_error:
      return "an exception that is not a pilempm::Error";
    case Outcome::signalled:
      return "killed by a signal";
    default:
      return "no answer within the time limit";
  }
}

using Clock = std::chrono::steady_clock;

// Reads `fd` into `out` until it closes (true) or the deadline passes (false).
bool read_until_closed(int fd, Clock::time_point deadline, std::string& out) {
  char buffer[4096];
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return false;
    pollfd ready{fd, POLLIN, 0};
    if (::poll(&ready, 1, static_cast<int>(left.count())) <= 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) return true;
    out.append(buffer, static_cast<std::size_t>(n));
  }
}

// The wait status of `child` once it ends, or nothing when the deadline passes first (it is
// killed then).
std::optional<int> wait_until(pid_t child, Clock::time_point deadline) {
  int status = 0;
  while (::waitpid(child, &status, WNOHANG) != child) {
    if (Clock::now() > deadline) {
      ::kill(child, SIGKILL);
      ::waitpid(child, nullptr, 0);
      return std::nullopt;
    }
    ::usleep(1000);
  }
  return status;
}

// Runs `body` in a child process with a time limit and 4 GiB of memory: its pilempm::Error's
// message comes back; anything else is reported as such.
Outcome run_isolated(const std::function<void()>& body, int seconds) {
  int pipe_ends[2];
  if (::pipe(pipe_ends) != 0) return {Outcome::foreign_error, 0, "pipe failed"};
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(pipe_ends[0]);
#ifndef __SANITIZE_ADDRESS__
    // (Not under AddressSanitizer: its shadow memory is terabytes of address space, and every
    // input then failed with "Failed to mmap"; the time limit still stops a runaway input.)
    const rlimit memory{rlim_t{4} << 30, rlim_t{4} << 30};
    ::setrlimit(RLIMIT_AS, &memory);
#endif
    int code = 0;
    std::string message;
    try {
      body();
    } catch (const Error& e) {
      message = e.what();
      code = 1;
    } catch (const std::exception& e) {
      message = e.what();
      code = 2;
    } catch (...) {
      code = 2;
    }
    for (std::size_t written = 0; written < message.size();) {
      const ssize_t n = ::write(pipe_ends[1], message.data() + written, message.size() - written);
      if (n <= 0) break;
      written += static_cast<std::size_t>(n);
    }
    ::_exit(code);
  }
  ::close(pipe_ends[1]);
  Outcome outcome;
  const auto deadline = Clock::now() + std::chrono::seconds(seconds);
  const bool closed = read_until_closed(pipe_ends[0], deadline, outcome.message);
  ::close(pipe_ends[0]);
  const std::optional<int> ended = wait_until(child, closed ? deadline : Clock::now());
  if (!ended) return {Outcome::hung, 0, outcome.message};
  const int status = *ended;
  if (WIFSIGNALED(status)) return {Outcome::signalled, WTERMSIG(status), outcome.message};
  const int code = WEXITSTATUS(status);
  outcome.kind = code == 0   ? Outcome::accepted
                 : code == 1 ? Outcome::rejected
                             : Outcome::foreign_error;
  return outcome;
}

// The seeds: example files of each kind, small enough to check in milliseconds.
struct CaseKind {
  const char* name;
  std::vector<std::string> files;  // relative to examples/
  std::function<void(const std::string& text, const std::string& source)> check;
};

std::vector<CaseKind> case_kinds() {
  return {
      {"element",
       {"element_tests.toml"},
       [](const std::string& text, const std::string& source) {
         (void)parse_element_case(text, source);
       }},
      {"mpm",
       {"mpm/column_self_weight.toml", "mpm/strip_footing_8.toml", "mpm/inclined_plane_slide.toml",
        "mpm/bar_vibration.toml", "mpm/restart_collapse.toml", "mpm/lame_cylinder_32.toml",
        "mpm/strip_footing_load_10.toml"},
       [](const std::string& text, const std::string& source) {
         (void)simulation::make_mpm_solver(read_mpm_case_text(text, source));
       }},
      {"centrifuge",
       {"centrifuge/quick.toml", "centrifuge/igs1_small.toml", "centrifuge/md_original.toml",
        "centrifuge/mpm4_modified_then_original.toml", "centrifuge/md_stress_dependent_alpha.toml"},
       [](const std::string& text, const std::string& source) {
         const scenario::CentrifugeScenario scenario = read_centrifuge_case_text(text, source);
         (void)centrifuge_to_mpm_case(scenario, source);
       }},
  };
}

// Keeps a failing input for a person to look at.
std::string keep(const std::string& text, const std::string& label) {
  const fs::path path =
      fs::temp_directory_path() / ("pilempm-fuzz-" + std::to_string(::getpid()) + "-" + label);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

void fuzz_case_files(int inputs_per_kind, std::uint64_t seed) {
  for (const CaseKind& kind : case_kinds()) {
    Random random(seed ^ std::hash<std::string>{}(kind.name));
    std::vector<std::string> seeds;
    for (const std::string& file : kind.files)
      seeds.push_back(read_text(fs::path(PILEMPM_SOURCE_DIR) / "examples" / file));
    int counts[5] = {0, 0, 0, 0, 0};
    int failures = 0;
    for (int k = 0; k < inputs_per_kind && failures < 5; ++k) {
      const std::size_t which = random.below(seeds.size());
      std::string text = seeds[which];
      const int mutations = 1 + static_cast<int>(random.below(3));
      for (int m = 0; m < mutations; ++m) text = mutate_text(text, random);
      const std::string source =
          std::string("fuzz/") + kind.name + "-" + std::to_string(k) + ".toml";
      const Outcome outcome = run_isolated([&] { kind.check(text, source); }, 20);
      ++counts[outcome.kind];
      const bool names_file = outcome.message.find(source) != std::string::npos;
      if (outcome.kind == Outcome::accepted || (outcome.kind == Outcome::rejected && names_file))
        continue;
      ++failures;
      ADD_FAILURE() << kind.name << " input " << k << " (from " << kind.files[which]
                    << "): " << kind_name(outcome.kind)
                    << (outcome.kind == Outcome::signalled ? " " + std::to_string(outcome.signal)
                                                           : std::string())
                    << (outcome.kind == Outcome::rejected ? " without naming the file" : "")
                    << "\n  message: " << outcome.message.substr(0, 500) << "\n  input kept in "
                    << keep(text, source.substr(5));
    }
    std::printf("[ fuzz %s ] %d inputs: %d accepted, %d rejected naming the file, %d other\n",
                kind.name, counts[0] + counts[1] + counts[2] + counts[3] + counts[4], counts[0],
                counts[1], counts[2] + counts[3] + counts[4]);
  }
}

// ---- the command line -------------------------------------------------------------------------

struct CommandOutcome {
  Outcome::Kind kind;
  int status;
  std::string output;
};

// Runs the pilempm program with `arguments` (no shell), its output collected, within `seconds`.
CommandOutcome run_program(const std::vector<std::string>& arguments, int seconds) {
  int pipe_ends[2];
  if (::pipe(pipe_ends) != 0) return {Outcome::foreign_error, -1, "pipe failed"};
  const pid_t child = ::fork();
  if (child == 0) {
    ::dup2(pipe_ends[1], 1);
    ::dup2(pipe_ends[1], 2);
    ::close(pipe_ends[0]);
    ::close(pipe_ends[1]);
    std::vector<char*> argv;
    std::string program = PILEMPM_BINARY;
    argv.push_back(program.data());
    std::vector<std::string> copies = arguments;
    for (std::string& a : copies) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(pipe_ends[1]);
  CommandOutcome outcome{Outcome::accepted, 0, ""};
  const auto deadline = Clock::now() + std::chrono::seconds(seconds);
  const bool closed = read_until_closed(pipe_ends[0], deadline, outcome.output);
  ::close(pipe_ends[0]);
  const std::optional<int> ended = wait_until(child, closed ? deadline : Clock::now());
  if (!ended) {
    outcome.kind = Outcome::hung;
    return outcome;
  }
  const int status = *ended;
  if (WIFSIGNALED(status)) {
    outcome.kind = Outcome::signalled;
    outcome.status = WTERMSIG(status);
  } else {
    outcome.status = WEXITSTATUS(status);
    outcome.kind = outcome.status == 0   ? Outcome::accepted
                   : outcome.status == 3 ? Outcome::foreign_error  // "internal error"
                                         : Outcome::rejected;
  }
  return outcome;
}

// Command lines that work, each option followed by its value.
std::vector<std::vector<std::string>> base_command_lines() {
  const std::string quick = std::string(PILEMPM_SOURCE_DIR) + "/examples/centrifuge/quick.toml";
  return {
      {"analytic", "bolton", "--id", "0.95", "--phi-c-deg", "31", "--p-kPa", "100,1000"},
      {"analytic", "rohe", "--sigma-v-MPa", "0.1,1,10"},
      {"analytic", "alpha", "--e0", "0.7", "--p-kPa", "100,1000"},
      {"element", "triaxial", "--set", "original", "--igs", "none", "--e0", "0.7", "--e0-at",
       "initial-stress", "--sigma3-kPa", "100", "--axial-strain", "0.05", "--steps", "200"},
      {"element", "oedometer", "--set", "original", "--igs", "none", "--e0", "0.7", "--e0-at",
       "initial-stress", "--sigma-v0-kPa", "10", "--sigma-v-kPa", "100,10", "--steps", "200"},
      {"element", "isotropic", "--set", "original", "--igs", "none", "--e0", "0.7", "--e0-at",
       "initial-stress", "--p0-kPa", "10", "--p-end-kPa", "1000", "--steps", "200"},
      {"centrifuge", "case", quick},
  };
}

void fuzz_command_line(int inputs, std::uint64_t seed) {
  Random random(seed);
  const auto bases = base_command_lines();
  int counts[5] = {0, 0, 0, 0, 0};
  int failures = 0;
  for (int k = 0; k < inputs && failures < 5; ++k) {
    std::vector<std::string> arguments = random.pick(bases);
    std::vector<std::size_t> values;  // indices of option values
    for (std::size_t i = 1; i < arguments.size(); ++i)
      if (arguments[i - 1].rfind("--", 0) == 0 && arguments[i].rfind("--", 0) != 0)
        values.push_back(i);
    std::string changed;  // the option whose value changed: the message must name it
    std::string changed_value;
    if (!values.empty() && random.below(4) != 0) {
      const std::size_t i = random.pick(values);
      static const std::vector<std::string> bad = {"",
                                                   " ",
                                                   "0",
                                                   "-1",
                                                   "1e300",
                                                   "-1e300",
                                                   "1e306",
                                                   "5e-324",
                                                   "nan",
                                                   "inf",
                                                   "-inf",
                                                   "1,",
                                                   ",",
                                                   "1,,2",
                                                   "abc",
                                                   "0x10",
                                                   "1e",
                                                   "\x1b[31m",
                                                   std::string(300, '9'),
                                                   "\xFF\xFE",
                                                   "400",
                                                   "2147483648",
                                                   "-2147483649",
                                                   "0.0",
                                                   "1e-300",
                                                   "1,nan"};
      arguments[i] = random.pick(bad);
      changed = arguments[i - 1];
      changed_value = arguments[i];
    } else if (random.below(2) == 0 && !values.empty()) {  // an option and its value left out
      const std::size_t i = random.pick(values);
      arguments.erase(arguments.begin() + static_cast<long>(i - 1),
                      arguments.begin() + static_cast<long>(i + 1));
    } else {  // an option given twice
      if (values.empty()) continue;
      const std::size_t i = random.pick(values);
      arguments.push_back(arguments[i - 1]);
      arguments.push_back(arguments[i]);
    }
    const CommandOutcome outcome = run_program(arguments, 60);
    ++counts[outcome.kind];
    std::string line;
    for (const auto& a : arguments) line += " '" + a + "'";
    // The option, or (for an error about a combination, e.g. a void ratio outside the model's
    // band at the changed stress) the changed value itself.
    const bool named =
        changed.empty() || outcome.output.find(changed) != std::string::npos ||
        (changed_value.size() >= 3 && outcome.output.find(changed_value) != std::string::npos);
    const bool clean =
        outcome.kind == Outcome::accepted || (outcome.kind == Outcome::rejected && named &&
                                              outcome.output.find('\x1b') == std::string::npos);
    if (clean) continue;
    ++failures;
    ADD_FAILURE() << "pilempm" << line << ": " << kind_name(outcome.kind) << " (status "
                  << outcome.status << ")"
                  << (outcome.kind == Outcome::rejected
                          ? " without naming " + changed + " or with a raw control character"
                          : std::string())
                  << "\n  output: " << outcome.output.substr(0, 600);
  }
  std::printf(
      "[ fuzz command line ] %d runs: %d accepted, %d rejected naming the option, %d other\n",
      counts[0] + counts[1] + counts[2] + counts[3] + counts[4], counts[0], counts[1],
      counts[2] + counts[3] + counts[4]);
}

TEST(FuzzCaseFiles, NoCrashNoHangAndEveryRejectionNamesTheFile) {
  fuzz_case_files(120, base_seed());
}

TEST(FuzzCommandLine, NoCrashNoHangAndEveryRejectionNamesTheOption) {
  fuzz_command_line(60, base_seed());
}

TEST(FuzzCaseFilesLong, NoCrashNoHangAndEveryRejectionNamesTheFile) {
  fuzz_case_files(4000, base_seed() + 1);
}

TEST(FuzzCommandLineLong, NoCrashNoHangAndEveryRejectionNamesTheOption) {
  fuzz_command_line(1500, base_seed() + 1);
}

}  // namespace
}  // namespace pilempm
