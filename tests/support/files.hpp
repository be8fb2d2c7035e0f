#pragma once
// Files of the tests: a file's whole text, and temporary folders named after the test and the
// process (so that two test binaries running at once never share one), removed afterwards.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace pilempm::test_support {

/// The whole text of a file, byte for byte ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `pilempm-NAME-<process id>` in the temporary folder, removed if it is there (not made).
inline std::filesystem::path fresh_temp_path(const std::string& name) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("pilempm-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  return path;
}

/// `pilempm-LABEL-<the running test's name>-<process id>` in the temporary folder, removed if it
/// is there (not made).
inline std::filesystem::path fresh_test_path(const std::string& label) {
  const auto* test = testing::UnitTest::GetInstance()->current_test_info();
  return fresh_temp_path(label + "-" + test->name());
}

/// A folder of the running test's own (fresh_test_path(label)), made empty or, with
/// `make = false`, left for the program under test to make; removed with everything in it at the
/// end of the test.
class TestDir {
 public:
  explicit TestDir(const std::string& label, bool make = true) : path_(fresh_test_path(label)) {
    if (make) std::filesystem::create_directories(path_);
  }
  ~TestDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TestDir(const TestDir&) = delete;
  TestDir& operator=(const TestDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// The path of `name` in the folder, as text (for command lines).
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace pilempm::test_support
