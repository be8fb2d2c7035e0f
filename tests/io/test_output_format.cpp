// The number and table formatters of every output file (io/output/format.hpp, json_writer.hpp):
// one rule for NaN, infinities and negative zero; digits that read back; quoting; tables.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/json_writer.hpp"

namespace pilempm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(OutputFormat, CsvNumberReadsBackToTheSameDouble) {
  for (const double value : {0.1, 1.0 / 3.0, -2.5e-7, 6.02214076e23, 123456.789, 1e-300}) {
    const std::string text = csv_number(value);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
  }
  EXPECT_EQ(csv_number(0.1), "0.1");  // the shortest text, not 17 digits
}

TEST(OutputFormat, CsvNumberRoundsToSignificantDigits) {
  EXPECT_EQ(csv_number(1.0 / 3.0, 10), "0.3333333333");
  EXPECT_EQ(csv_number(123456.789, 6), "123457");
  EXPECT_EQ(csv_number(2.5e-7, 4), "2.5e-07");
  // Rounding to 10 digits and reading back gives the same text again: what a copy of a column
  // of a curve file prints.
  const double value = 6.514954540123;
  const std::string text = csv_number(value, 10);
  EXPECT_EQ(csv_number(std::strtod(text.c_str(), nullptr)), text);
}

TEST(OutputFormat, NotANumberAndNegativeZeroHaveOneRule) {
  // CSV: a number strtod reads back; JSON: null; for a person: "-".
  EXPECT_EQ(csv_number(kNaN), "nan");
  EXPECT_EQ(csv_number(-kNaN, 6), "nan");
  EXPECT_EQ(csv_number(kInf), "inf");
  EXPECT_EQ(csv_number(-kInf, 8), "-inf");
  EXPECT_TRUE(std::isnan(std::strtod(csv_number(kNaN).c_str(), nullptr)));
  EXPECT_EQ(json_number(kNaN), "null");
  EXPECT_EQ(json_number(-kInf, 6), "null");
  EXPECT_EQ(fixed_number(kNaN, 2), "-");
  EXPECT_EQ(shown_number(kInf, "{:.3g}"), "-");
  // A negated zero is zero.
  EXPECT_EQ(csv_number(-0.0), "0");
  EXPECT_EQ(csv_number(-0.0, 10), "0");
  EXPECT_EQ(json_number(-0.0), "0");
  EXPECT_EQ(fixed_number(-0.0, 2), "0.00");
  EXPECT_EQ(shown_number(-0.0, "{:g}"), "0");
  // Other numbers as given.
  EXPECT_EQ(fixed_number(-1.005, 1), "-1.0");
  EXPECT_EQ(shown_number(1234.5678, "{:.3g}"), "1.23e+03");
  EXPECT_EQ(json_number(1.0 / 3.0, 6), "0.333333");
}

TEST(OutputFormat, CsvFieldsAreQuotedOnlyWhereNeeded) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_row({"a", "b,c", ""}), "a,\"b,c\",\n");
  CsvText csv("what it is", {"x_kPa", "y"});
  csv.add({"1", "2"});
  EXPECT_EQ(csv.text(), "# what it is\nx_kPa,y\n1,2\n");
  EXPECT_EQ(CsvText("", {"a"}).text(), "a\n");
}

TEST(OutputFormat, MarkdownTableAlignsAndEscapes) {
  EXPECT_EQ(markdown_table({"name", "value [kPa]"}, {{"a|b", "1"}, {"two\nlines", "2"}}),
            "| name | value [kPa] |\n"
            "| --- | ---: |\n"
            "| a\\|b | 1 |\n"
            "| two lines | 2 |\n");
  EXPECT_EQ(markdown_table({"x", "y"}, {}, 0), "| x | y |\n| ---: | ---: |\n");
}

TEST(OutputFormat, JsonWriterNestsAndWritesNullForNaN) {
  JsonWriter j;
  j.string("name", "a\"b").number("x", 0.1).number("missing", kNaN);
  j.object("inner").integer("n", 3).boolean("ok", true).numbers("list", {1.0, -0.0, kInf}).end();
  EXPECT_EQ(j.finish(),
            "{\n"
            "  \"name\": \"a\\\"b\",\n"
            "  \"x\": 0.1,\n"
            "  \"missing\": null,\n"
            "  \"inner\": {\n"
            "    \"n\": 3,\n"
            "    \"ok\": true,\n"
            "    \"list\": [1, 0, null]\n"
            "  }\n"
            "}\n");
}

}  // namespace
}  // namespace pilempm
