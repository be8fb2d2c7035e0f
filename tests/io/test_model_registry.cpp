// A model added by one folder (path_length_elastic/) and the one registration line below, used
// through the registry only: read from a [[material]] table, run in an element test and in MPM,
// its history written to a checkpoint and read back.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>

#include "../support/mpm_case_texts.hpp"
#include "path_length_elastic/path_length_elastic.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm {
namespace {

using namespace simulation;
using testing::PathLengthElastic;

const bool kRegistered = register_model(testing::path_length_elastic_registration());

const char* const kElementCase = R"(
[[material]]
name = "toy"
model = "path-length-elastic"
shear_modulus_MPa = 30
bulk_modulus_MPa = 50

[[test]]
name = "path"
type = "strain-path"
set = "toy"
e0 = 0.7
e0_at = "initial-stress"
initial_stress_kPa = [100, 100, 100]
segments = [ { strain = [-0.002, 0, 0], steps = 20 },
             { strain = [0.001, 0, 0, 0, 0, 0.0005], steps = 10 } ]
)";

TEST(ModelRegistry, ATestModelIsReadFromAMaterialTableThroughTheRegistry) {
  ASSERT_TRUE(kRegistered);
  const ElementCaseFile file = parse_element_case(kElementCase, "case.toml");
  ASSERT_EQ(file.tests.size(), 1u);
  const ElementCase& c = file.tests[0];
  EXPECT_EQ(c.material.model, "path-length-elastic");
  const auto* p = c.material.parameters_as<testing::PathLengthElasticParameters>();
  ASSERT_NE(p, nullptr);
  EXPECT_DOUBLE_EQ(p->shear_modulus, 30e6);  // MPa -> Pa
  EXPECT_DOUBLE_EQ(p->bulk_modulus, 50e6);
  EXPECT_NE(dynamic_cast<const PathLengthElastic*>(c.model.get()), nullptr);
}

TEST(ModelRegistry, ATestModelsKeysAreStrict) {
  std::string text = kElementCase;
  text.replace(text.find("bulk_modulus_MPa"), 16, "bulk_modulus_GPa");
  try {
    parse_element_case(text, "case.toml");
    FAIL() << "a misspelt key of the test model was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "case.toml");
    // The misspelt key's line (6): the reader took it for the missing bulk_modulus_MPa.
    EXPECT_EQ(e.line(), 6);
    EXPECT_NE(std::string(e.what()).find("bulk_modulus"), std::string::npos) << e.what();
  }
}

// Elastic: the final stress is the initial one plus C : (total strain) whatever the path, and the
// history holds the path length sum ||Δε|| = 20 x ||Δε_1|| + 10 x ||Δε_2||.
TEST(ModelRegistry, ATestModelRunsInAnElementTest) {
  const ElementCaseFile file = parse_element_case(kElementCase, "case.toml");
  const ElementCase& c = file.tests[0];
  const ElementResult result = run_element_test(*c.model, c.test, c.initial);
  const double G = 30e6, K = 50e6;
  const double e11 =
      0.002 - 0.001;  // at the end, tension positive (the file: compression positive)
  const CurvePoint& end = result.curve.back();
  EXPECT_NEAR(end.axial_strain, -e11, 1e-15);
  // Strain-path tests drive every component: sigma_11 = -p0 + (K + 4G/3) e11.
  EXPECT_NEAR(end.axial_stress, 100e3 - (K + 4.0 / 3.0 * G) * e11, 1e-6);
  EXPECT_NEAR(end.radial_stress, 100e3 - (K - 2.0 / 3.0 * G) * e11, 1e-6);

  MaterialState state = initial_state(*c.model, -100e3 * identity6(), c.initial);
  Vec6 d1 = Vec6::Zero(), d2 = Vec6::Zero();
  d1[k11] = -0.002 / 20;
  d2[k11] = 0.001 / 10;
  d2[k12] = 0.0005 * kSqrt2 / 10;
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(c.model->update(state, d1).ok);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(c.model->update(state, d2).ok);
  EXPECT_NEAR(PathLengthElastic::path_length(state), 20 * d1.norm() + 10 * d2.norm(), 1e-15);
}

// A ground of the test model under 20 g, settling.
std::string toy_ground_case() {
  using namespace test_support;
  return mpm_case_opening(
             {.x_max_m = 0.4,
              .x_cells = 4,
              .y_max_m = 0.6,
              .y_cells = 6,
              .boundaries = kRollerRightFixedBase,
              .solver = "gravity_multiplier = 20.0\nlocal_damping = 0.1\nthreads = 1\n"}) +
         R"([[material]]
name = "toy"
model = "path-length-elastic"
shear_modulus_MPa = 30
bulk_modulus_MPa = 50
)" +
         mpm_region_text({.x_max_m = 0.4,
                          .density_kg_per_m3 = 1600.0,
                          .material = "toy",
                          .initial_stress = "zero"}) +
         R"([[phase]]
duration_s = 1.0
output_interval_s = 1.0
)";
}

bool same_histories(const mpm::Particles& a, const mpm::Particles& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(a.state[i].history.data(), b.state[i].history.data(),
                    sizeof(a.state[i].history)) != 0)
      return false;
  return true;
}

// The model's history variable goes through a checkpoint by the name the model declares: a
// fresh solver of the same case (history zero) gets it back bitwise, and both continue alike.
TEST(ModelRegistry, ATestModelsHistoryGoesThroughACheckpoint) {
  const MpmCase mpm_case = read_mpm_case_text(toy_ground_case(), "toy.toml");
  mpm::Solver run = make_mpm_solver(mpm_case);
  for (int k = 0; k < 30; ++k) run.step();  // the sand settles under 20 g
  double largest = 0.0;
  for (const MaterialState& s : run.particles().state)
    largest = std::max(largest, PathLengthElastic::path_length(s));
  ASSERT_GT(largest, 0.0) << "no history to store";

  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("pilempm-registry-" + std::to_string(::getpid()) + ".h5");
  MpmCheckpointInfo info;
  info.case_source = "toy.toml";
  info.initial_position = run.particles().position;
  write_mpm_checkpoint(file, run, info);
  mpm::Solver restarted = make_mpm_solver(mpm_case);
  ASSERT_FALSE(same_histories(run.particles(), restarted.particles()));
  read_mpm_checkpoint(file, restarted);
  std::filesystem::remove(file);
  EXPECT_TRUE(same_histories(run.particles(), restarted.particles()));
  for (int k = 0; k < 10; ++k) {
    run.step();
    restarted.step();
  }
  EXPECT_TRUE(same_histories(run.particles(), restarted.particles()));
  for (std::size_t i = 0; i < run.particles().size(); ++i)
    ASSERT_EQ(std::memcmp(run.particles().state[i].stress.data(),
                          restarted.particles().state[i].stress.data(), 6 * sizeof(double)),
              0);
}

}  // namespace
}  // namespace pilempm
