// igs_initial in element case files: the names and the explicit tensor.
#include <gtest/gtest.h>

#include "pilempm/io/element_case.hpp"

namespace {

using namespace pilempm;

std::string case_with(const std::string& igs_initial) {
  return "[[test]]\nname = \"oed\"\ntype = \"oedometer\"\nset = \"original\"\nigs = \"IGS3\"\n"
         "e0 = 0.7\ne0_at = \"initial-stress\"\nsigma_v0_kPa = 10\nsigma_v_kPa = 400\n"
         "igs_initial = " +
         igs_initial + "\n";
}

TEST(ElementCaseIgsInitial, NamesAndTensorAreRead) {
  EXPECT_EQ(parse_element_case(case_with("\"first-increment\""), "c.toml").tests[0].initial.igs,
            InitialCondition::Igs::first_increment);
  const ElementCase c = parse_element_case(case_with("[1e-4, 0, 0]"), "c.toml").tests[0];
  EXPECT_EQ(c.initial.igs, InitialCondition::Igs::tensor);
  // Compression positive in the file, tension positive inside.
  EXPECT_DOUBLE_EQ(c.initial.igs_tensor[0], -1e-4);
  EXPECT_DOUBLE_EQ(c.initial.igs_tensor.tail<5>().norm(), 0.0);
}

TEST(ElementCaseIgsInitial, ATensorLongerThanRIsAnErrorAtItsKey) {
  try {
    parse_element_case(case_with("[2e-4, 0, 0]"), "c.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("c.toml:10"), std::string::npos) << m;
    EXPECT_NE(m.find("igs_initial"), std::string::npos) << m;
    EXPECT_NE(m.find("norm <= R"), std::string::npos) << m;
  }
  EXPECT_THROW(parse_element_case(case_with("\"sideways\""), "c.toml"), InputError);
}

}  // namespace
