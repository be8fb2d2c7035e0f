// Reading numeric CSV back, and the figures description of the plotting script.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/json_writer.hpp"
#include "pilempm/study/csv_table.hpp"
#include "pilempm/study/figures.hpp"

namespace pilempm {
namespace {

TEST(NumericCsv, ReadsCommentHeaderAndNumbers) {
  const NumericTable t =
      parse_numeric_csv("# a comment\nx_kPa,y_pct\r\n1,2.5\n-3e2,nan\n", "test.csv");
  ASSERT_EQ(t.columns().size(), 2u);
  EXPECT_EQ(t.rows(), 2u);
  EXPECT_TRUE(t.has("y_pct"));
  EXPECT_EQ(t.column("x_kPa")[1], -300.0);
  EXPECT_EQ(t.column("y_pct")[0], 2.5);
  EXPECT_TRUE(std::isnan(t.column("y_pct")[1]));
}

TEST(NumericCsv, ErrorsNameTheFileLineAndColumn) {
  try {
    parse_numeric_csv("a,b\n1,2\n3,x\n", "curve.csv");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("curve.csv:3: column b: \"x\""), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_numeric_csv("a,b\n1\n", "c.csv"), Error);
  EXPECT_THROW(parse_numeric_csv("# only a comment\n", "c.csv"), Error);
  const NumericTable t = parse_numeric_csv("a,b\n1,2\n", "c.csv");
  try {
    t.column("q_kPa");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no column \"q_kPa\" (columns: a, b)"), std::string::npos)
        << e.what();
  }
}

FigureSpec example_figure() {
  FigureSpec f;
  f.file = "a.png";
  f.title = "Title with \"quotes\" and $\\sigma$";
  f.cols = 2;
  PanelSpec p;
  p.x = {"stress [kPa]", true, std::pair{1.0, 100.0}};
  p.y = {"void ratio e [-]", false, {}};
  SeriesSpec s;
  s.csv = "a.csv";
  s.where = {{"test", "t1"}};
  s.x = "sigma_kPa";
  s.y = "void_ratio";
  s.label = "t1";
  p.series = {s, s};
  p.series[1].csv = "b.csv";
  f.panels = {p, p};
  return f;
}

TEST(FiguresJson, WritesEveryFieldTheScriptReads) {
  const std::string json = figures_json({example_figure()});
  for (const char* expected :
       {"\"version\": 1", "\"file\": \"a.png\"", "\"layout\": [1, 2]",
        "\"title\": \"Title with \\\"quotes\\\" and $\\\\sigma$\"",
        "\"x\": {\"label\": \"stress [kPa]\", \"log\": true, \"limits\": [1, 100]}",
        "\"y\": {\"label\": \"void ratio e [-]\"}", "\"where\": {\"test\": \"t1\"}",
        "\"csv\": \"b.csv\"", "\"linestyle\": \"-\""})
    EXPECT_NE(json.find(expected), std::string::npos) << expected << "\n" << json;
  EXPECT_EQ(figure_csv_files({example_figure(), example_figure()}),
            (std::vector<std::string>{"a.csv", "b.csv"}));
}

TEST(FiguresJson, RejectsPanelsThatDoNotFitAndNonFiniteLimits) {
  FigureSpec f = example_figure();
  f.cols = 1;
  EXPECT_THROW(figures_json({f}), Error);
  f = example_figure();
  f.panels[0].x.limits = std::pair{0.0, std::nan("")};
  EXPECT_THROW(figures_json({f}), Error);
}

TEST(FiguresJson, QuotesControlCharacters) {
  EXPECT_EQ(json_quote("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
}

}  // namespace
}  // namespace pilempm
