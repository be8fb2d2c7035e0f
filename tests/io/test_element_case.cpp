// Element case files: a valid file gives the tests in SI, and every mistake gives one message
// with the file, the line, the key, the value and what is allowed.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../support/input_texts.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/io/element_case.hpp"

namespace pilempm {
namespace {

InputError case_error(const std::string& text) {
  return test_support::input_error_of(text, [&] { (void)parse_element_case(text, "case.toml"); });
}

// The first lines of a triaxial [[test]] "a" with its void ratio but not its convention (line 1
// is [[test]]).
const std::string kTriaxialTestA = R"([[test]]
name = "a"
type = "triaxial"
set = "original"
igs = "IGS3"
e0 = 0.6
)";

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const char* kValid = R"(title = "t"
[defaults]
set = "original"
igs = "IGS3"
e0_at = "initial-stress"

[integrator]
tolerance = 1e-4
scheme = "bogacki-shampine"

[[material]]
name = "soft"
model = "hypoplastic"
base = "original"
h_s_MPa = 1000
igs = { base = "IGS3", R = 5e-5 }

[[material]]
name = "elastic"
model = "linear-elastic"
young_modulus_MPa = 50
poisson_ratio = 0.3

[[test]]
name = "tx-1"
type = "triaxial"
e0 = 0.59
sigma3_kPa = 50
axial_strain = 0.2
steps = 100

[[test]]
name = "oed-cyclic"
type = "oedometer"
set = "loose-fit"
igs = "none"
igs_initial = "zero"
e0 = 0.567
e0_at = "zero-pressure"
sigma_v0_kPa = 10
K0 = 0.5
sigma_v_kPa = [400, 100, 400]
steps_per_segment = 20

[[test]]
name = "iso"
type = "isotropic"
set = "soft"
e0 = 0.7
p0_kPa = 10
p_end_kPa = 1000

[[test]]
name = "ux"
type = "undrained-triaxial"
set = "elastic"
e0 = 0.7
p0_kPa = 100
axial_strain = 0.01

[[test]]
name = "path"
type = "strain-path"
e0 = 0.7
initial_stress_kPa = [100, 50, 50]
segments = [ { strain = [0.01, 0, 0], steps = 10 },
             { strain = [-0.005, 0, 0, 0, 0, 0.002], steps = 5 } ]
)";

TEST(ElementCase, ValidFileGivesTheTestsInSi) {
  const ElementCaseFile file = parse_element_case(kValid, "case.toml");
  EXPECT_EQ(file.title, "t");
  ASSERT_EQ(file.tests.size(), 5u);

  const ElementCase& tx = file.tests[0];
  EXPECT_EQ(tx.name, "tx-1");
  EXPECT_EQ(tx.source, "case.toml:24");
  const auto& t = std::get<DrainedTriaxialTest>(tx.test);
  EXPECT_DOUBLE_EQ(t.sigma3, 50e3);
  EXPECT_DOUBLE_EQ(t.axial_strain, 0.2);
  EXPECT_EQ(t.steps, 100);
  EXPECT_DOUBLE_EQ(tx.initial.e0, 0.59);
  EXPECT_EQ(tx.initial.e0_at, VoidRatioConvention::at_initial_stress);  // from [defaults]
  EXPECT_EQ(tx.initial.igs, InitialCondition::Igs::compression);
  EXPECT_EQ(tx.material.name, "original");
  ASSERT_TRUE(tx.igs.has_value());
  EXPECT_EQ(tx.igs->name, "IGS3");
  EXPECT_DOUBLE_EQ(tx.integrator.tolerance, 1e-4);
  EXPECT_EQ(tx.integrator.scheme, IntegratorSettings::Scheme::bogacki_shampine);
  const auto* hypo = dynamic_cast<const Hypoplastic*>(tx.model.get());
  ASSERT_NE(hypo, nullptr);
  EXPECT_DOUBLE_EQ(hypo->parameters().h_s, 4e9);
  EXPECT_DOUBLE_EQ(hypo->intergranular().R, 1e-4);
  EXPECT_DOUBLE_EQ(hypo->integrator().tolerance, 1e-4);

  const ElementCase& oed = file.tests[1];
  const auto& o = std::get<OedometerTest>(oed.test);
  EXPECT_DOUBLE_EQ(o.sigma_v0, 10e3);
  EXPECT_EQ(o.sigma_v_targets, (std::vector<double>{400e3, 100e3, 400e3}));
  EXPECT_EQ(o.steps_per_segment, 20);
  EXPECT_EQ(oed.initial.e0_at, VoidRatioConvention::at_zero_pressure);
  EXPECT_EQ(oed.initial.igs, InitialCondition::Igs::zero);
  EXPECT_EQ(oed.igs->name, "none");
  EXPECT_FALSE(dynamic_cast<const Hypoplastic&>(*oed.model).intergranular().enabled());
  EXPECT_DOUBLE_EQ(dynamic_cast<const Hypoplastic&>(*oed.model).parameters().h_s, 2e9);

  const ElementCase& iso = file.tests[2];
  EXPECT_EQ(iso.material.name, "soft");
  EXPECT_EQ(iso.material.hypoplastic_material().base, "original");
  const auto& soft = dynamic_cast<const Hypoplastic&>(*iso.model);
  EXPECT_DOUBLE_EQ(soft.parameters().h_s, 1e9);
  EXPECT_DOUBLE_EQ(soft.parameters().e_c0, 0.929);  // from the base set
  EXPECT_DOUBLE_EQ(soft.intergranular().R, 5e-5);   // the material's igs beats [defaults]
  EXPECT_DOUBLE_EQ(soft.intergranular().chi, 1.0);
  EXPECT_EQ(std::get<IsotropicCompressionTest>(iso.test).steps, 400);  // default

  const ElementCase& ux = file.tests[3];
  EXPECT_EQ(ux.material.model, "linear-elastic");
  EXPECT_DOUBLE_EQ(ux.initial.e0, 0.7);
  EXPECT_FALSE(ux.igs.has_value());

  const auto& path = std::get<StrainPathTest>(file.tests[4].test);
  EXPECT_DOUBLE_EQ(path.initial_stress[k11], -100e3);  // compression positive in the file
  EXPECT_DOUBLE_EQ(path.initial_stress[k22], -50e3);
  ASSERT_EQ(path.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(path.segments[0].strain[k11], -0.01);
  EXPECT_DOUBLE_EQ(path.segments[1].strain[k11], 0.005);
  EXPECT_DOUBLE_EQ(path.segments[1].strain[k12], -0.002 * kSqrt2);  // tensor shear, Mandel
  EXPECT_EQ(path.segments[1].steps, 5);
}

TEST(ElementCase, UnknownKeyInATestNamesFileLineAndFullKey) {
  const InputError e = case_error(kTriaxialTestA + R"(e0_at = "initial-stress"
sigma3_kPa = 50
axial_strain = 0.2
stpes = 100
)");
  EXPECT_EQ(e.line(), 10);
  EXPECT_EQ(e.key(), "test[0].stpes");
  EXPECT_TRUE(contains(e.what(), "case.toml:10: test[0].stpes = 100: unknown key")) << e.what();
  EXPECT_TRUE(contains(e.what(), "did you mean \"steps\"")) << e.what();
}

TEST(ElementCase, UnknownTopLevelKeyAndDefaultsKey) {
  EXPECT_EQ(case_error("tilte = \"x\"\n").key(), "tilte");
  const InputError e = case_error("[defaults]\nset = \"original\"\nsigma3_kPa = 50\n");
  EXPECT_EQ(e.key(), "defaults.sigma3_kPa");
  EXPECT_EQ(e.line(), 3);
}

TEST(ElementCase, MaterialWithEc0BelowEd0IsRejectedAtItsLine) {
  const InputError e = case_error(R"(
[[material]]
name = "bad"
model = "hypoplastic"
phi_c_deg = 31
h_s_MPa = 4000
n = 0.42
e_d0 = 0.9
e_c0 = 0.8
e_i0 = 1.1
alpha = 0.12
beta = 1.0
)");
  EXPECT_EQ(e.line(), 9);
  EXPECT_EQ(e.key(), "material[0].e_c0");
  EXPECT_TRUE(
      contains(e.what(), "case.toml:9: material[0].e_c0 = 0.8: not allowed: must be > e_d0 = 0.9"))
      << e.what();
}

TEST(ElementCase, MaterialOverrideFromBaseIsChecked) {
  // e_i0 below the base set's e_c0 = 0.929.
  const InputError e = case_error(
      "[[material]]\nname = \"m\"\nmodel = \"hypoplastic\"\nbase = \"original\"\ne_i0 = 0.9\n");
  EXPECT_EQ(e.line(), 5);
  EXPECT_TRUE(contains(e.what(), "e_i0 = 0.9")) << e.what();
  EXPECT_TRUE(contains(e.what(), "> e_c0 = 0.929")) << e.what();
}

TEST(ElementCase, MaterialValuesAreRangeChecked) {
  const InputError e = case_error(
      "[[material]]\nname = \"m\"\nmodel = \"hypoplastic\"\nbase = \"original\"\nn = 1.5\n");
  EXPECT_EQ(std::string(e.what()),
            "case.toml:5: material[0].n = 1.5: out of range: must be in (0, 1)");
  const InputError mc = case_error(R"([[material]]
name = "mc"
model = "mohr-coulomb"
young_modulus_MPa = 50
poisson_ratio = 0.3
cohesion_kPa = 0
friction_angle_deg = 30
dilatancy_angle_deg = 35
)");
  EXPECT_EQ(mc.line(), 8);
  EXPECT_TRUE(contains(mc.what(), "dilatancy_angle_deg = 35: out of range: must be in [0, 30]"))
      << mc.what();
  const InputError name =
      case_error("[[material]]\nname = \"original\"\nmodel = \"hypoplastic\"\n");
  EXPECT_TRUE(contains(name.what(), "built-in set")) << name.what();
}

TEST(ElementCase, MissingE0AtIsAnErrorListingBothConventions) {
  const InputError e = case_error(kTriaxialTestA + R"(sigma3_kPa = 50
axial_strain = 0.2
)");
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.key(), "test[0].e0_at");
  EXPECT_TRUE(contains(e.what(), "\"initial-stress\"")) << e.what();
  EXPECT_TRUE(contains(e.what(), "\"zero-pressure\"")) << e.what();
}

TEST(ElementCase, DuplicateTestNamesAreRejected) {
  const std::string test =
      "[[test]]\nname = \"{}\"\ntype = \"isotropic\"\np0_kPa = 10\np_end_kPa = 100\n";
  std::string text =
      "[defaults]\nset = \"original\"\nigs = \"none\"\ne0 = 0.7\ne0_at = \"initial-stress\"\n";
  for (const char* name : {"iso-a", "iso-b", "ISO-A"}) {
    std::string t = test;
    t.replace(t.find("{}"), 2, name);
    text += t;
  }
  const InputError e = case_error(text);
  EXPECT_EQ(e.key(), "test[2].name");
  EXPECT_EQ(e.line(), 17);
  EXPECT_TRUE(contains(e.what(), "duplicate")) << e.what();
  EXPECT_TRUE(contains(e.what(), "case.toml:6")) << e.what();  // where the first one is
}

TEST(ElementCase, TestNamesMustBeSafeFileNames) {
  EXPECT_EQ(test_name_problem("tx-dense_50kPa.e0.59"), "");
  EXPECT_NE(test_name_problem("../escape"), "");
  EXPECT_NE(test_name_problem("a/b"), "");
  EXPECT_NE(test_name_problem("with space"), "");
  EXPECT_NE(test_name_problem(""), "");
  EXPECT_NE(test_name_problem(".hidden"), "");
  EXPECT_NE(test_name_problem("Summary"), "");
  const InputError e = case_error("[[test]]\nname = \"a/b\"\ntype = \"isotropic\"\n");
  EXPECT_EQ(e.key(), "test[0].name");
  EXPECT_EQ(e.line(), 2);
}

TEST(ElementCase, BadValuesInTestsNameKeyValueAndRange) {
  const std::string head =
      "[defaults]\nset = \"original\"\nigs = \"IGS3\"\ne0 = 0.7\ne0_at = \"initial-stress\"\n"
      "[[test]]\nname = \"a\"\n";
  const InputError sigma =
      case_error(head + "type = \"triaxial\"\nsigma3_kPa = -50\naxial_strain = 0.2\n");
  EXPECT_EQ(std::string(sigma.what()),
            "case.toml:9: test[0].sigma3_kPa = -50: out of range: must be > 0");
  const InputError type = case_error(head + "type = \"triax\"\n");
  EXPECT_TRUE(contains(type.what(), "test[0].type = \"triax\": not allowed: must be one of"))
      << type.what();
  const InputError set = case_error(head + "type = \"triaxial\"\nset = \"orignal\"\n");
  EXPECT_TRUE(contains(set.what(), "case.toml:9: test[0].set = \"orignal\": unknown"))
      << set.what();
  EXPECT_TRUE(contains(set.what(), "modified-medium-dense")) << set.what();
  const InputError igs = case_error(head + "type = \"triaxial\"\nigs = \"IGS5\"\n");
  EXPECT_TRUE(contains(igs.what(), "IGS1")) << igs.what();
  const InputError steps =
      case_error(head + "type = \"triaxial\"\nsigma3_kPa = 50\naxial_strain = 0.2\nsteps = 0\n");
  EXPECT_EQ(steps.key(), "test[0].steps");
  // e0 that the model cannot take at that stress: outside [e_d, e_i].
  const InputError e0 = case_error(
      "[[test]]\nname = \"a\"\ntype = \"triaxial\"\nset = \"original\"\nigs = \"IGS3\"\ne0 = 0.4\n"
      "e0_at = \"initial-stress\"\nsigma3_kPa = 100\naxial_strain = 0.2\n");
  EXPECT_EQ(e0.line(), 6);
  EXPECT_TRUE(contains(e0.what(), "[e_d, e_i]")) << e0.what();
}

TEST(ElementCase, IntergranularStrainIsRequiredForHypoplasticAndRejectedForOthers) {
  const InputError missing = case_error(
      "[[test]]\nname = \"a\"\ntype = \"isotropic\"\nset = \"original\"\ne0 = 0.7\n"
      "e0_at = \"initial-stress\"\np0_kPa = 10\np_end_kPa = 100\n");
  EXPECT_EQ(missing.key(), "test[0].igs");
  const InputError elastic = case_error(
      "[[material]]\nname = \"el\"\nmodel = \"linear-elastic\"\nyoung_modulus_MPa = 10\n"
      "poisson_ratio = 0.2\n[[test]]\nname = \"a\"\ntype = \"isotropic\"\nset = \"el\"\n"
      "igs = \"IGS3\"\ne0 = 0.7\ne0_at = \"zero-pressure\"\np0_kPa = 10\np_end_kPa = 100\n");
  EXPECT_EQ(elastic.key(), "test[0].igs");
  EXPECT_EQ(elastic.line(), 10);
  // Scaling e0 from zero pressure needs the hypoplastic h_s and n.
  const InputError scaled = case_error(
      "[[material]]\nname = \"el\"\nmodel = \"linear-elastic\"\nyoung_modulus_MPa = 10\n"
      "poisson_ratio = 0.2\n[[test]]\nname = \"a\"\ntype = \"isotropic\"\nset = \"el\"\n"
      "e0 = 0.7\ne0_at = \"zero-pressure\"\np0_kPa = 10\np_end_kPa = 100\n");
  EXPECT_EQ(scaled.key(), "test[0].e0_at");
  EXPECT_EQ(scaled.line(), 11);
  const InputError table = case_error(
      "[[test]]\nname = \"a\"\ntype = \"isotropic\"\nset = \"original\"\n"
      "igs = { m_R = 5, m_T = 6, R = 1e-4, beta_r = 1, chi = 1 }\n");
  EXPECT_TRUE(contains(table.what(), "m_R = 5")) << table.what();
  EXPECT_TRUE(contains(table.what(), ">= m_T = 6")) << table.what();
}

TEST(ElementCase, IntegratorTableIsStrict) {
  const InputError e = case_error("[integrator]\ntolerence = 1e-4\n");
  EXPECT_EQ(e.key(), "integrator.tolerence");
  EXPECT_TRUE(contains(e.what(), "did you mean \"tolerance\"")) << e.what();
}

TEST(ElementCase, EmptyFileNeedsATest) {
  EXPECT_TRUE(contains(case_error("title = \"x\"\n").what(), "[[test]]"));
}

TEST(ElementCase, BuiltInExampleParsesAndSaysItsConventions) {
  const ElementCaseFile file = builtin_element_case();
  EXPECT_EQ(file.source, kBuiltinElementCaseName);
  EXPECT_GE(file.tests.size(), 30u);
  int zero_pressure = 0;
  for (const ElementCase& c : file.tests) {
    if (c.initial.e0_at == VoidRatioConvention::at_zero_pressure) ++zero_pressure;
  }
  EXPECT_GE(zero_pressure, 10);  // the high-pressure and alpha series
}

}  // namespace
}  // namespace pilempm

namespace pilempm {
namespace {

TEST(ElementCase, OedometerK0DefaultsToJakyForHypoplasticSets) {
  const ElementCaseFile file = parse_element_case(
      "[[test]]\nname = \"oed\"\ntype = \"oedometer\"\nset = \"modified-loose\"\nigs = \"none\"\n"
      "e0 = 0.75\ne0_at = \"initial-stress\"\nsigma_v0_kPa = 10\nsigma_v_kPa = 400\n",
      "case.toml");
  EXPECT_NEAR(std::get<OedometerTest>(file.tests[0].test).K0, 0.5, 1e-12);  // 1 - sin 30 deg
  // Other models have no phi_c: K0 is required.
  const InputError e = case_error(
      "[[material]]\nname = \"el\"\nmodel = \"linear-elastic\"\nyoung_modulus_MPa = 10\n"
      "poisson_ratio = 0.2\n[[test]]\nname = \"a\"\ntype = \"oedometer\"\nset = \"el\"\n"
      "e0 = 0.7\ne0_at = \"initial-stress\"\nsigma_v0_kPa = 10\nsigma_v_kPa = 400\n");
  EXPECT_EQ(e.key(), "test[0].K0");
}

}  // namespace
}  // namespace pilempm
