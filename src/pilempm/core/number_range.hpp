#pragma once
// Allowed ranges of input numbers and the names input uses for library keys: shared by every
// reader of parameters (the TOML case files of io/, the parameter readers of the models).
#include <functional>
#include <limits>
#include <map>
#include <string>

namespace pilempm {

/// An allowed interval for a number, each end open, closed or unbounded.
struct NumberRange {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lower_open = false;
  bool upper_open = false;

  static NumberRange any() { return {}; }
  static NumberRange positive() { return {0.0, kInf, true, false}; }         // > 0
  static NumberRange non_negative() { return {0.0, kInf, false, false}; }    // >= 0
  static NumberRange above(double a) { return {a, kInf, true, false}; }      // > a
  static NumberRange at_least(double a) { return {a, kInf, false, false}; }  // >= a
  static NumberRange open(double a, double b) { return {a, b, true, true}; }
  static NumberRange closed(double a, double b) { return {a, b, false, false}; }
  static NumberRange left_open(double a, double b) { return {a, b, true, false}; }  // (a, b]

  /// Finite and inside the interval.
  bool contains(double value) const;
  /// "> 0", ">= 1", "in (0, 1)", "in (0, 0.1]", "any finite number".
  std::string describe() const;

  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

/// Maps the keys that library validation (InvalidValue) uses to the keys of the input, where
/// they differ (e.g. "h_s_Pa" -> "h_s_MPa").
using KeyMap = std::map<std::string, std::string, std::less<>>;

}  // namespace pilempm
