#pragma once
// The input texts of the tests (case files, tables) edited one key at a time, and the error that
// reading one raises.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "pilempm/core/error.hpp"

namespace pilempm::test_support {

/// `text` with the first `from` replaced by `to`; a test failure, and `text` unchanged, when
/// `from` is not in it.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The 1-based line of the first occurrence of `needle` in `text`.
inline long line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  if (at == std::string::npos) return 0;
  return 1 +
         static_cast<long>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

/// The InputError that `read()` throws reading `text`; a test failure naming the text, and an
/// empty error, when it throws none.
template <class Read>
InputError input_error_of(const std::string& text, Read read) {
  try {
    read();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return InputError("", 0, "", "", "");
}

}  // namespace pilempm::test_support
