// Output folders (io/output/output_folder.hpp): a folder that holds another run's files is refused
// unless asked to overwrite, which removes exactly that run's files (listed, or of the names only
// pilempm writes) and keeps foreign ones; a run continuing its own folder keeps it; every file
// written below a claimed folder is listed; stray temporary files of stopped runs are removed,
// those of running processes kept; a full disk is an error that leaves no temporary file.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/files.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/output_folder.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;
using test_support::read_text;

class OutputFolder : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test_support::fresh_test_path("output-folder"); }
  void TearDown() override { fs::remove_all(dir_); }

  static void touch(const fs::path& path, const std::string& text = "x\n") {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }
  // The names in the folder and below it, relative to it, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> all;
    for (const auto& entry : fs::recursive_directory_iterator(dir_))
      all.push_back(entry.path().lexically_relative(dir_).generic_string());
    std::sort(all.begin(), all.end());
    return all;
  }
  fs::path dir_;
};

// The id of a process that has ended (a child waited for).
pid_t ended_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST_F(OutputFolder, AFolderWithAnotherRunIsRefusedAndOverwriteRemovesOnlyThatRunsFiles) {
  claim_output_folder(dir_);
  write_file_atomically(dir_ / "run_one.csv", "1\n");
  fs::create_directories(dir_ / "mpm");
  write_file_atomically(dir_ / "mpm" / "snapshot.vtu", "2\n");
  touch(dir_ / "notes.txt");  // the user's own file
  const std::string list = read_text(dir_ / kOutputListName);
  EXPECT_NE(list.find("run_one.csv\n"), std::string::npos) << list;
  EXPECT_NE(list.find("mpm/snapshot.vtu\n"), std::string::npos) << list;

  try {
    claim_output_folder(dir_);
    FAIL() << "a folder with another run was taken";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(dir_.string()), std::string::npos) << what;
    EXPECT_NE(what.find("another run"), std::string::npos) << what;
    EXPECT_NE(what.find("run_one.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("--overwrite"), std::string::npos) << what;
  }
  EXPECT_TRUE(fs::exists(dir_ / "run_one.csv"));  // a refusal changes nothing

  OutputFolderOptions overwrite;
  overwrite.overwrite = true;
  const OutputFolderClaim claim = claim_output_folder(dir_, overwrite);
  EXPECT_EQ(claim.removed_files.size(), 2u);
  EXPECT_EQ(names(), std::vector<std::string>{"notes.txt"});  // mpm/ was emptied and removed
  // The new run's list starts empty and the folder can be taken again only with overwrite.
  write_file_atomically(dir_ / "run_two.csv", "3\n");
  EXPECT_EQ(read_text(dir_ / kOutputListName), "run_two.csv\n");
}

TEST_F(OutputFolder, ForeignFilesAloneAreNotAnotherRun) {
  touch(dir_ / "notes.txt");
  touch(dir_ / "data.csv");
  touch(dir_ / "README.md");
  touch(dir_ / "sub" / "summary.json");  // a foreign subfolder is not looked into
  EXPECT_TRUE(earlier_run_files(dir_).empty());
  EXPECT_NO_THROW(claim_output_folder(dir_));
  EXPECT_EQ(names(), (std::vector<std::string>{"README.md", "data.csv", "notes.txt", "sub",
                                               "sub/summary.json"}));
}

TEST_F(OutputFolder, ARunOfAnOlderPilempmIsRecognisedByTheNamesOnlyPilempmWrites) {
  for (const char* name :
       {"particles.pvd", "particles_00003.vtu", "bodies_00003.vtu", "checkpoint_02_installation.h5",
        "pile.csv", "fields_installation.vtu", "summary.json", "mpm/energies.csv"})
    touch(dir_ / name);
  for (const char* name :
       {"particles_final.vtu", "bodies_final.vtu", "checkpoint.h5", "my.vtu", "notes.txt"})
    touch(dir_ / name);  // not names pilempm writes
  EXPECT_EQ(earlier_run_files(dir_).size(), 8u);
  EXPECT_THROW(claim_output_folder(dir_), Error);
  OutputFolderOptions overwrite;
  overwrite.overwrite = true;
  EXPECT_EQ(claim_output_folder(dir_, overwrite).removed_files.size(), 8u);
  EXPECT_EQ(names(), (std::vector<std::string>{"bodies_final.vtu", "checkpoint.h5", "my.vtu",
                                               "notes.txt", "particles_final.vtu"}));
}

TEST_F(OutputFolder, ARunContinuingItsOwnFolderKeepsItAndItsList) {
  claim_output_folder(dir_);
  write_file_atomically(dir_ / "checkpoint_01_k0.h5", "c\n");
  OutputFolderOptions resume;
  resume.resume = true;
  const OutputFolderClaim claim = claim_output_folder(dir_, resume);
  EXPECT_TRUE(claim.removed_files.empty());
  EXPECT_TRUE(fs::exists(dir_ / "checkpoint_01_k0.h5"));
  write_file_atomically(dir_ / "checkpoint_01_k0.h5", "d\n");  // listed once
  write_file_atomically(dir_ / "checkpoint_02_jack.h5", "e\n");
  EXPECT_EQ(read_text(dir_ / kOutputListName), "checkpoint_01_k0.h5\ncheckpoint_02_jack.h5\n");
}

TEST_F(OutputFolder, TheListOfANestedRunFolderHoldsItsOwnFiles) {
  claim_output_folder(dir_);           // a study
  claim_output_folder(dir_ / "case");  // one of its runs
  write_file_atomically(dir_ / "README.md", "r\n");
  write_file_atomically(dir_ / "case" / "pile.csv", "p\n");
  EXPECT_EQ(read_text(dir_ / kOutputListName), "README.md\n");
  EXPECT_EQ(read_text(dir_ / "case" / kOutputListName), "pile.csv\n");
  // Overwriting the study removes its runs' files too.
  touch(dir_ / "case" / "mine.txt");
  OutputFolderOptions overwrite;
  overwrite.overwrite = true;
  EXPECT_EQ(claim_output_folder(dir_, overwrite).removed_files.size(), 2u);
  EXPECT_EQ(names(), (std::vector<std::string>{"case", "case/mine.txt"}));
}

TEST_F(OutputFolder, StrayTemporaryFilesOfStoppedRunsAreRemovedThoseOfRunningOnesKept) {
  const pid_t ended = ended_process();
  const std::string dead = std::to_string(ended);
  const std::string alive = std::to_string(::getppid());
  touch(dir_ / ("energies.csv." + dead + "-3.tmp"));
  touch(dir_ / "mpm" / ("particles_00001.vtu." + dead + "-7.tmp"));
  touch(dir_ / "bodies.csv.tmp");                  // the fixed name of older versions
  touch(dir_ / ("pile.csv." + alive + "-1.tmp"));  // a process that still runs
  touch(dir_ / "mine.tmp");                        // not pilempm's
  touch(dir_ / ("notes.txt." + dead + "-x.tmp"));  // not the pattern
  OutputFolderOptions resume;                      // (the folder holds no run)
  resume.resume = true;
  const OutputFolderClaim claim = claim_output_folder(dir_, resume);
  EXPECT_EQ(claim.removed_temporary.size(), 3u);
  EXPECT_EQ(names(), (std::vector<std::string>{"mine.tmp", "mpm", "notes.txt." + dead + "-x.tmp",
                                               "pile.csv." + alive + "-1.tmp"}));
}

TEST_F(OutputFolder, OwnTemporaryFilesAreRemovedAtTheEnd) {
  claim_output_folder(dir_);
  const fs::path own = temporary_path_for(dir_ / "mpm" / "bodies.csv");
  touch(own);
  touch(dir_ / ("pile.csv." + std::to_string(::getppid()) + "-1.tmp"));
  const std::vector<fs::path> removed = remove_own_temporary_files();
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed.front(), own);
  EXPECT_FALSE(fs::exists(own));
  EXPECT_TRUE(fs::exists(dir_ / ("pile.csv." + std::to_string(::getppid()) + "-1.tmp")));
}

// A full disk (a file-size limit of 0 in a child process) is an error naming the file, leaves no
// temporary file and an older file as it was.
TEST_F(OutputFolder, AFullDiskIsAnErrorAndLeavesNoTemporaryFile) {
  fs::create_directories(dir_);
  touch(dir_ / "old.csv", "old\n");
  const pid_t child = ::fork();
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{0, 0};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 10;
    try {
      write_file_atomically(dir_ / "old.csv", "new content\n");
    } catch (const Error& e) {
      code = std::string(e.what()).find("old.csv") != std::string::npos ? 0 : 11;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no error, 11: the message does not name the file";
  EXPECT_EQ(read_text(dir_ / "old.csv"), "old\n");
  EXPECT_EQ(names(), std::vector<std::string>{"old.csv"});
}

}  // namespace
}  // namespace pilempm
