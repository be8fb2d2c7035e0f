// Input that passes a plain range check but breaks what the program does with the value, and
// names that cannot serve: each is refused where it enters, naming the user's file, line and key.
#include <gtest/gtest.h>

#include <string>

#include "../support/input_texts.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm {
namespace {

// A small plane-strain MPM case of 35 lines; line numbers below refer to it: [geometry] on line 1,
// [[material]] on 17, [[region]] on 22 (its last line, initial_stress, on 31), [[phase]] on 32
// and the phase's name on 33.
std::string mpm_case() {
  using namespace test_support;
  return mpm_case_opening({.x_cells = 4, .y_cells = 4, .boundaries = "bottom = \"fixed\"\n"}) +
         linear_elastic_material_text("soil", 10.0) +
         mpm_region_text({.name = "block",
                          .density_kg_per_m3 = 1800.0,
                          .material = "soil",
                          .initial_stress = "zero"}) +
         R"([[phase]]
name = "settle"
duration_s = 0.01
output_interval_s = 0.01
)";
}

using test_support::replaced;

std::string mpm_error(const std::string& text) {
  try {
    (void)simulation::make_mpm_solver(read_mpm_case_text(text, "case.toml"));
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "case.toml");
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(NumberRange, MagnitudesThatOverflowAfterConversionAreOutOfRange) {
  EXPECT_TRUE(NumberRange::positive().contains(1e100));
  EXPECT_FALSE(NumberRange::positive().contains(1e306));
  EXPECT_FALSE(NumberRange::any().contains(-1e306));
  EXPECT_FALSE(NumberRange::positive().contains(5e-324));
  EXPECT_TRUE(NumberRange::non_negative().contains(0.0));
  EXPECT_TRUE(NumberRange::positive().contains(1e-100));
  EXPECT_TRUE(has(NumberRange::positive().problem(1e306), "magnitude"));
  EXPECT_TRUE(has(NumberRange::positive().problem(-1.0), "must be > 0"));
}

TEST(MpmInputLimits, TractionOf1e306KPaIsRefusedAtItsKey) {
  // 1e306 kPa is 1e309 Pa: infinite, formerly reported later as a NaN particle.
  const std::string text =
      mpm_case() + "[[traction]]\nregion = \"block\"\nside = \"top\"\nnormal_kPa = 1e306\n";
  const std::string message = mpm_error(text);
  EXPECT_TRUE(has(message, "case.toml:39: traction[0].normal_kPa = 1e+306")) << message;
}

TEST(MpmInputLimits, InitialVelocityOf1e300IsRefusedAtItsKey) {
  const std::string message =
      mpm_error(replaced(mpm_case(), "initial_stress = \"zero\"\n[[phase]]",
                         "initial_stress = \"zero\"\nvelocity_x_m_per_s = 1e300\n[[phase]]"));
  EXPECT_TRUE(has(message, "case.toml:32: region[0].velocity_x_m_per_s = 1e+300")) << message;
  EXPECT_TRUE(has(message, "in [-10000, 10000]")) << message;
}

TEST(MpmInputLimits, RegionWithoutParticlesIsRefusedNamingIt) {
  // Narrower than a particle's spacing: formerly "no finite wave speed ... in step 1 (0 m/s)".
  const std::string message =
      mpm_error(replaced(mpm_case(), "x_max_m = 1.0\ny_min_m", "x_max_m = 0.01\ny_min_m"));
  EXPECT_TRUE(has(message, "case.toml:22: region[0]")) << message;
  EXPECT_TRUE(has(message, "region \"block\" holds no particle")) << message;
}

TEST(MpmInputLimits, LongPhaseNameIsRefusedBeforeTheRun) {
  // A 300-character phase name ran the phase, then could not write its checkpoint.
  const std::string message = mpm_error(
      replaced(mpm_case(), "name = \"settle\"", "name = \"" + std::string(300, 'p') + "\""));
  EXPECT_TRUE(has(message, "case.toml:33: phase[0].name")) << message;
  EXPECT_TRUE(has(message, "1 to 100 letters")) << message;
  EXPECT_LT(message.size(), 400u) << message;  // the value is cut
  const std::string slash = mpm_error(replaced(mpm_case(), "name = \"block\"", "name = \"a/b\""));
  EXPECT_TRUE(has(slash, "region[0].name")) << slash;
}

const char* const kCentrifugeCase = R"(title = "limits"
[sand]
material = "original"
e0 = 0.68
e0_at = "initial-stress"
[installation]
wished_in_place_D = 3.0
depth_D = 2.0
velocity_m_per_s = 0.025
[mesh]
cells_per_D = 4
)";

std::string centrifuge_error(const std::string& text) {
  try {
    (void)read_centrifuge_case_text(text, "user.toml");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "user.toml") << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

TEST(CentrifugeInputLimits, CaseRefusesATinyJackingSpeedAtTheUsersKey) {
  // `centrifuge case` took 5e-324 m/s; `centrifuge run` then refused it as
  // "mpm_case.toml:103 phase[1].duration_s", a file and key the user never wrote.
  (void)read_centrifuge_case_text(kCentrifugeCase, "user.toml");  // the base case is valid
  const std::string message = centrifuge_error(
      replaced(kCentrifugeCase, "velocity_m_per_s = 0.025", "velocity_m_per_s = 5e-324"));
  EXPECT_TRUE(has(message, "user.toml:9: installation.velocity_m_per_s = 5e-324")) << message;
  EXPECT_FALSE(has(message, "mpm_case.toml")) << message;
}

TEST(CentrifugeInputLimits, CaseChecksWhatTheMpmCaseWouldRefuse) {
  // 20 km/s passes the centrifuge file's own check (> 0) but not the MPM case's speed limit:
  // the message names the user's file.
  const std::string message = centrifuge_error(
      replaced(kCentrifugeCase, "velocity_m_per_s = 0.025", "velocity_m_per_s = 2e4"));
  EXPECT_TRUE(has(message, "user.toml")) << message;
  EXPECT_TRUE(has(message, "MPM case that is not valid")) << message;
}

}  // namespace
}  // namespace pilempm
