// The strict TOML reader: every error names the file, the line, the full key, the value and
// what is allowed; unknown keys and wrong types are errors.
#include <gtest/gtest.h>

#include <string>

#include "pilempm/io/toml_reader.hpp"

namespace pilempm {
namespace {

// Runs `read` and returns the InputError it throws (fails the test when it throws nothing).
template <class F>
InputError error_of(F read) {
  try {
    read();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", 0, "", "", "");
}

TEST(NumberRange, DescribesItself) {
  EXPECT_EQ(NumberRange::positive().describe(), "> 0");
  EXPECT_EQ(NumberRange::at_least(1).describe(), ">= 1");
  EXPECT_EQ(NumberRange::open(0, 1).describe(), "in (0, 1)");
  EXPECT_EQ(NumberRange::left_open(0, 0.1).describe(), "in (0, 0.1]");
  EXPECT_TRUE(NumberRange::open(0, 1).contains(0.5));
  EXPECT_FALSE(NumberRange::open(0, 1).contains(1.0));
  EXPECT_TRUE(NumberRange::left_open(0, 0.1).contains(0.1));
  EXPECT_FALSE(NumberRange::any().contains(std::numeric_limits<double>::quiet_NaN()));
}

TEST(TableReader, ReadsTypedKeysAndConvertsIntegers) {
  const toml::table doc =
      parse_toml_text("a = 3\nb = 2.5\nname = \"x\"\nlist = [1, 2.5]\n", "f.toml");
  TableReader r(doc, "f.toml", "");
  EXPECT_DOUBLE_EQ(r.number("a", NumberRange::positive()), 3.0);
  EXPECT_DOUBLE_EQ(r.number("b", NumberRange::positive()), 2.5);
  EXPECT_EQ(r.string("name"), "x");
  EXPECT_EQ(r.number_array("list", NumberRange::any(), 1, 5), (std::vector<double>{1.0, 2.5}));
  EXPECT_DOUBLE_EQ(r.number_or("absent", 7.0, NumberRange::any()), 7.0);
  EXPECT_NO_THROW(r.check_no_unknown_keys());
}

TEST(TableReader, UnknownKeyNamesFileLineKeyAndSuggestsTheIntendedOne) {
  const toml::table doc = parse_toml_text(
      "[[test]]\nname = \"a\"\n\n[[test]]\nname = \"b\"\nsigma3_kpa = 50\n", "case.toml");
  TableReader root(doc, "case.toml", "");
  std::vector<TableReader> tests = root.tables("test");
  ASSERT_EQ(tests.size(), 2u);
  TableReader& t = tests[1];
  t.string("name");
  t.optional_number("sigma3_kPa", NumberRange::positive());
  const InputError e = error_of([&] { t.check_no_unknown_keys(); });
  EXPECT_EQ(e.file(), "case.toml");
  EXPECT_EQ(e.line(), 6);
  EXPECT_EQ(e.key(), "test[1].sigma3_kpa");
  const std::string what = e.what();
  EXPECT_NE(what.find("case.toml:6: test[1].sigma3_kpa = 50: unknown key"), std::string::npos)
      << what;
  EXPECT_NE(what.find("did you mean \"sigma3_kPa\""), std::string::npos) << what;
}

TEST(TableReader, OutOfRangeValueGivesKeyValueAndRange) {
  const toml::table doc = parse_toml_text("\n[integrator]\ntolerance = 0.5\n", "c.toml");
  TableReader root(doc, "c.toml", "");
  TableReader integrator = *root.table("integrator");
  const InputError e =
      error_of([&] { integrator.number("tolerance", NumberRange::left_open(0.0, 0.1)); });
  EXPECT_EQ(std::string(e.what()),
            "c.toml:3: integrator.tolerance = 0.5: out of range: must be in (0, 0.1]");
}

TEST(TableReader, WrongTypeIsAnError) {
  const toml::table doc = parse_toml_text("steps = 2000.5\ne0 = \"dense\"\n", "c.toml");
  TableReader r(doc, "c.toml", "");
  const InputError steps = error_of([&] { r.integer("steps", 1, 100000); });
  EXPECT_EQ(steps.line(), 1);
  EXPECT_NE(std::string(steps.what()).find("expected an integer, got a floating-point number"),
            std::string::npos);
  const InputError e0 = error_of([&] { r.number("e0", NumberRange::positive()); });
  EXPECT_EQ(std::string(e0.what()),
            "c.toml:2: e0 = \"dense\": wrong type: expected a number, got a string");
}

TEST(TableReader, ArrayElementErrorNamesTheElement) {
  const toml::table doc = parse_toml_text("sigma_v_kPa = [400,\n  -100]\n", "c.toml");
  TableReader r(doc, "c.toml", "");
  const InputError e =
      error_of([&] { r.number_array("sigma_v_kPa", NumberRange::positive(), 1, 10, true); });
  EXPECT_EQ(e.key(), "sigma_v_kPa[1]");
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(std::string(e.what()).find("must be > 0"), std::string::npos);
}

TEST(TableReader, MissingKeyAndChoiceListTheAllowedValues) {
  const toml::table doc = parse_toml_text("[t]\nscheme = \"rk4\"\n", "c.toml");
  TableReader root(doc, "c.toml", "");
  TableReader t = *root.table("t");
  const InputError bad = error_of([&] { t.choice("scheme", {"heun-euler", "bogacki-shampine"}); });
  EXPECT_EQ(std::string(bad.what()),
            "c.toml:2: t.scheme = \"rk4\": not allowed: must be one of \"heun-euler\", "
            "\"bogacki-shampine\"");
  const InputError missing = error_of([&] { t.number("e0", NumberRange::positive()); });
  EXPECT_EQ(missing.key(), "t.e0");
  EXPECT_EQ(missing.line(), 1);  // the table's header
  EXPECT_NE(std::string(missing.what()).find("missing"), std::string::npos);
}

TEST(TableReader, LibraryValidationBecomesAnErrorAtTheKey) {
  const toml::table doc = parse_toml_text("[m]\nh_s_MPa = -4\n", "c.toml");
  TableReader root(doc, "c.toml", "");
  TableReader m = *root.table("m");
  const InputError e = m.error_from(InvalidValue("h_s_Pa", "-4e6", "> 0"), {{"h_s_Pa", "h_s_MPa"}});
  EXPECT_EQ(std::string(e.what()), "c.toml:2: m.h_s_MPa = -4: not allowed: must be > 0");
  // A key that is not in the table: the error points at the table and says where it came from.
  const InputError from_base = m.error_from(InvalidValue("e_c0", "0.4", "> e_d0"), {}, "from base");
  EXPECT_EQ(from_base.line(), 1);
  EXPECT_EQ(from_base.key(), "m.e_c0");
}

TEST(ParseToml, SyntaxErrorHasTheLine) {
  const InputError e = error_of([] { parse_toml_text("a = 1\nb = = 2\n", "bad.toml"); });
  EXPECT_EQ(e.file(), "bad.toml");
  EXPECT_EQ(e.line(), 2);
}

TEST(ParseToml, MissingFileIsAnInputError) {
  const InputError e = error_of([] { parse_toml_file("/nonexistent/dir/case.toml"); });
  EXPECT_EQ(e.file(), "/nonexistent/dir/case.toml");
}

}  // namespace
}  // namespace pilempm

namespace pilempm {
namespace {

std::string dotted_key(int levels) {
  std::string key = "x";
  for (int i = 1; i < levels; ++i) key += ".x";
  return key;
}

// Before the limits, 13 000 levels overflowed the stack in toml_text (from
// check_no_unknown_keys) and 31 000 inside toml++'s parser: SIGSEGV without a message.
TEST(TomlLimits, DeepDottedKeysAndHeadersAreRefusedWithFileAndLine) {
  for (const int levels : {40, 13000, 40000}) {
    const std::string key = dotted_key(levels);
    for (const std::string& text :
         {"a = 1\n" + key + " = 1\n", "a = 1\n[" + key + "]\nb = 2\n", "a = 1\n[[" + key + "]]\n",
          "a = 1\nb = { " + key + " = 1 }\n"}) {
      try {
        const toml::table doc = parse_toml_text(text, "deep.toml");
        TableReader r(doc, "deep.toml", "");
        r.check_no_unknown_keys();
        ADD_FAILURE() << "accepted " << levels << " levels";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "deep.toml");
        EXPECT_EQ(e.line(), 2);
        EXPECT_NE(std::string(e.what()).find("at most 32"), std::string::npos) << e.what();
      }
    }
  }
}

TEST(TomlLimits, KeysUpToTheLimitAndDotsInStringsAndNumbersAreAccepted) {
  const std::string key = dotted_key(kMaxTomlKeyDepth);
  const std::string dots(5000, '.');
  const toml::table doc =
      parse_toml_text(key + " = 1.5\ns = \"" + dots + "\"\nt = '''\n" + dots + "\n'''\n# " + dots +
                          "\nv = [1.5, 2.5, 3.5]\n" + "d = 1979-05-27T07:32:00.999\n",
                      "ok.toml");
  EXPECT_EQ(doc["s"].value<std::string>()->size(), dots.size());
  const toml::node* leaf = &doc;
  for (int i = 0; i < kMaxTomlKeyDepth; ++i) leaf = leaf->as_table()->get("x");
  EXPECT_DOUBLE_EQ(leaf->value<double>().value_or(0.0), 1.5);
}

TEST(TomlLimits, DeepArraysAndInlineTablesAreRefused) {
  for (const std::string& open : {std::string("["), std::string("{ y = ")}) {
    std::string text = "a = 1\nv = ";
    for (int i = 0; i < 100000; ++i) text += open;
    try {
      parse_toml_text(text, "nest.toml");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), 2);
      EXPECT_NE(std::string(e.what()).find("nest.toml:2: arrays and inline tables nested 33"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(TomlLimits, OversizedTextIsRefusedBeforeParsing) {
  const std::string text(kMaxTomlBytes + 1, '#');
  try {
    parse_toml_text(text, "big.toml");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "big.toml");
  }
}

TEST(TomlText, LongValuesAreCutAndControlCharactersEscapedInMessages) {
  // 100 three-byte characters: the cut must fall between characters, and an ESC must not reach
  // the terminal.
  std::string value;
  for (int i = 0; i < 100; ++i) value += "\xE2\x82\xAC";  // the euro sign
  const toml::table doc = parse_toml_text("name = \"\\u001b[31m" + value + "\"\n", "f.toml");
  TableReader r(doc, "f.toml", "");
  const std::string message = error_of([&] { r.check_no_unknown_keys(); }).what();
  EXPECT_EQ(message.find('\x1b'), std::string::npos) << message;
  EXPECT_NE(message.find("\\x1B[31m"), std::string::npos) << message;
  EXPECT_LT(message.size(), 2000u);
  // Every byte sequence in the message is whole UTF-8: no lead byte without its continuation.
  const std::size_t cut = message.find("...");
  ASSERT_NE(cut, std::string::npos) << message;
  EXPECT_EQ(message.substr(cut - 3, 3), "\xE2\x82\xAC");
}

}  // namespace
}  // namespace pilempm
