// The runs of a study as child processes (process_pool.hpp): how many run at once, what each
// child gets (its environment, its log), how a child that fails or cannot start is reported,
// that the outcomes come in the order of the runs whatever order they end in; and the command
// lines for GNU parallel or a Slurm array, read back by a real shell.
#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pilempm/study/process_pool.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;

class ProcessPool : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pilempm-process-pool-" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // A child running `script` in /bin/sh, its output into NAME.log.
  ChildRun shell(const std::string& name, const std::string& script) const {
    return ChildRun{name, {"/bin/sh", "-c", script}, dir_ / (name + ".log")};
  }
  static std::string text_of(const fs::path& file) {
    std::ifstream in(file);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

// Two children that each wait (up to 20 s) for the other's file: they end only when both run at
// the same time.
std::string meet(const fs::path& mine, const fs::path& other) {
  return "touch '" + mine.string() + "'; i=0; while [ ! -e '" + other.string() +
         "' ] && [ $i -lt 200 ]; do sleep 0.1; i=$((i+1)); done; [ -e '" + other.string() + "' ]";
}

TEST_F(ProcessPool, TwoJobsRunTwoChildrenAtOnceOneJobRunsThemInTurn) {
  const std::vector<ChildRun> runs{shell("a", meet(dir_ / "a.here", dir_ / "b.here")),
                                   shell("b", meet(dir_ / "b.here", dir_ / "a.here"))};
  const std::vector<ChildOutcome> together = run_children(runs, 2, {});
  ASSERT_EQ(together.size(), 2u);
  EXPECT_TRUE(together[0].succeeded()) << together[0].how_it_ended();
  EXPECT_TRUE(together[1].succeeded()) << together[1].how_it_ended();

  // One job: never two at a time (each child fails when it finds another one's lock file).
  const std::string lock = (dir_ / "lock").string();
  const std::string alone = "if [ -e '" + lock + "' ]; then exit 7; fi; touch '" + lock +
                            "'; sleep 0.3; rm '" + lock + "'";
  const std::vector<ChildRun> three{shell("x", alone), shell("y", alone), shell("z", alone)};
  for (const ChildOutcome& o : run_children(three, 1, {}))
    EXPECT_TRUE(o.succeeded()) << o.how_it_ended();
}

TEST_F(ProcessPool, EachChildGetsTheEnvironmentChangesAndWritesItsOwnLog) {
  ::setenv("PILEMPM_POOL_KEPT", "kept", 1);
  ::setenv("OMP_NUM_THREADS", "8", 1);
  const std::vector<ChildRun> runs{
      shell("one", "echo \"$OMP_NUM_THREADS $PILEMPM_POOL_KEPT one\"; echo oops >&2"),
      shell("two",
            "echo \"$OMP_NUM_THREADS $PILEMPM_POOL_KEPT two\"; read line; echo \"[$line]\"")};
  const std::vector<ChildOutcome> outcomes = run_children(runs, 2, {"OMP_NUM_THREADS=1"});
  ::unsetenv("PILEMPM_POOL_KEPT");
  ::unsetenv("OMP_NUM_THREADS");
  for (const ChildOutcome& o : outcomes) EXPECT_TRUE(o.succeeded()) << o.how_it_ended();
  // The change replaces the variable (not a second entry), the rest is kept; standard error
  // goes to the log too; standard input is empty (/dev/null).
  EXPECT_EQ(text_of(dir_ / "one.log"), "1 kept one\noops\n");
  EXPECT_EQ(text_of(dir_ / "two.log"), "1 kept two\n[]\n");
}

TEST_F(ProcessPool, FailedChildrenAreReportedTheOthersStillRunOutcomesInRunOrder) {
  // The first child ends last: the calls come in the order the children end, the outcomes in
  // the order of the runs.
  const std::vector<ChildRun> runs{
      shell("slow", "sleep 0.5; exit 0"),
      shell("fails", "echo failing; exit 3"),
      shell("killed", "kill -9 $$"),
      ChildRun{"missing", {(dir_ / "no-such-program").string()}, dir_ / "missing.log"},
      ChildRun{"no-log", {"/bin/true"}, dir_ / "no-such-folder" / "x.log"},
      shell("fine", "exit 0")};
  std::vector<std::size_t> ended;
  const std::vector<ChildOutcome> o = run_children(
      runs, 3, {}, [&ended](std::size_t k, const ChildOutcome&) { ended.push_back(k); });
  ASSERT_EQ(o.size(), runs.size());
  ASSERT_EQ(ended.size(), runs.size());
  EXPECT_EQ(ended.back(), 0u);  // the slow one
  EXPECT_TRUE(o[0].succeeded());
  EXPECT_GE(o[0].wall_seconds, 0.5);
  EXPECT_EQ(o[1].exit_code, 3);
  EXPECT_EQ(o[1].how_it_ended(), "exit code 3");
  EXPECT_EQ(text_of(dir_ / "fails.log"), "failing\n");
  EXPECT_EQ(o[2].signal, SIGKILL);
  EXPECT_FALSE(o[2].succeeded());
  EXPECT_NE(o[2].how_it_ended().find("killed by signal 9"), std::string::npos);
  EXPECT_FALSE(o[3].started);
  EXPECT_NE(o[3].how_it_ended().find("no-such-program"), std::string::npos) << o[3].problem;
  EXPECT_FALSE(o[4].started);
  EXPECT_NE(o[4].problem.find("cannot write its log"), std::string::npos) << o[4].problem;
  EXPECT_TRUE(o[5].succeeded());
}

TEST_F(ProcessPool, AnExceptionOfTheCallbackComesWhenTheRunningChildrenHaveEnded) {
  const auto later = [this](const std::string& name, const std::string& seconds) {
    return shell(name, "sleep " + seconds + "; touch '" + (dir_ / (name + ".done")).string() + "'");
  };
  const std::vector<ChildRun> runs{later("first", "0"), later("second", "0.5"),
                                   later("third", "0")};
  int calls = 0;
  EXPECT_THROW(run_children(runs, 2, {},
                            [&calls](std::size_t, const ChildOutcome&) {
                              ++calls;
                              throw std::runtime_error("the callback failed");
                            }),
               std::runtime_error);
  EXPECT_EQ(calls, 1);
  EXPECT_TRUE(fs::exists(dir_ / "second.done"));  // ended before the exception came back
  EXPECT_FALSE(fs::exists(dir_ / "third.done"));  // never started
}

TEST_F(ProcessPool, CommandLinesReadBackByAShellGiveTheSameArguments) {
  // Each argument printed on a line of its own by the shell that runs the command line.
  const std::vector<std::string> arguments{"/usr/bin/printf",
                                           "%s\\n",
                                           "plain-word_1.toml",
                                           "with space",
                                           "it's",
                                           "$HOME",
                                           "`id`",
                                           "a\"b",
                                           "tab\there",
                                           "*",
                                           "",
                                           "semi;colon",
                                           "back\\slash"};
  ChildRun run{"printf", arguments, dir_ / "it's a log.txt"};
  EXPECT_EQ(shell_word("plain-word_1.toml"), "plain-word_1.toml");
  EXPECT_EQ(shell_word("it's"), "'it'\\''s'");
  EXPECT_EQ(shell_word(""), "''");
  const std::string line = shell_command(run, {"PILEMPM_X=${PILEMPM_X:-1}"});
  EXPECT_EQ(line.rfind("PILEMPM_X=${PILEMPM_X:-1} /usr/bin/printf ", 0), 0u) << line;
  const std::string script = dir_ / "line.sh";
  std::ofstream(script) << line << "\n";
  ASSERT_EQ(std::system(("/bin/sh '" + script + "'").c_str()), 0) << line;
  std::string expected;
  for (std::size_t k = 2; k < arguments.size(); ++k) expected += arguments[k] + "\n";
  EXPECT_EQ(text_of(dir_ / "it's a log.txt"), expected) << line;
}

}  // namespace
}  // namespace pilempm
