// whole_number: the whole text is one number, or there is none.
#include <gtest/gtest.h>

#include <cmath>

#include "pilempm/core/number_text.hpp"

namespace pilempm {
namespace {

TEST(WholeNumber, ReadsTheWholeTextAsOneNumber) {
  EXPECT_EQ(whole_number("1.5"), 1.5);
  EXPECT_EQ(whole_number("-2e-3"), -2e-3);
  EXPECT_EQ(whole_number("0.10000000000000001"), 0.1);  // what {:.17g} writes reads back
  ASSERT_TRUE(whole_number("nan").has_value());
  EXPECT_TRUE(std::isnan(*whole_number("nan")));
  EXPECT_EQ(whole_number("-inf"), -HUGE_VAL);
  EXPECT_EQ(whole_number("1e999"), HUGE_VAL);  // out of range: the caller's NumberRange decides
  EXPECT_EQ(whole_number(" 2"), 2.0);          // as after the comma of "1, 2"
}

TEST(WholeNumber, AnythingElseIsNoNumber) {
  for (const char* text : {"", " ", "1.5 ", "1.5x", "x", "1,5", "1.5\t2", "--1", "e3"})
    EXPECT_FALSE(whole_number(text).has_value()) << '"' << text << '"';
  const char with_zero[] = {'1', '\0', '2'};
  EXPECT_FALSE(whole_number(std::string_view(with_zero, 3)).has_value());
}

// The number a person would write: what the case files and the energy tolerance rule use.
TEST(WithSignificantDigits, GivesTheNumberOfItsDecimalText) {
  EXPECT_NE(100.0 * 1e-4 * 1e-4, 1e-6);  // the product is off by an ulp ...
  EXPECT_EQ(with_significant_digits(100.0 * 1e-4 * 1e-4, 9), 1e-6);  // ... its 9 digits are not
  EXPECT_EQ(with_significant_digits(0.123456789123, 3), 0.123);
  EXPECT_EQ(with_significant_digits(-2.5e-7, 17), -2.5e-7);
}

}  // namespace
}  // namespace pilempm
