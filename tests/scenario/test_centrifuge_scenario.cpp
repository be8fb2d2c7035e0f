// The centrifuge scenario as physics: the defaults of K0 and δ from the installation set's φ_c,
// the phases the case will have, the checks that the pieces fit together, and the sand density.
// (The MPM case text it writes is read back in tests/io/test_centrifuge_case.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"

namespace pilempm {
namespace {

using namespace scenario;

double sin_deg(double degrees) {
  return std::sin(degrees * std::numbers::pi / 180.0);
}

// The key of the InvalidValue validate() throws ("" when it throws none).
std::string invalid_key(const CentrifugeScenario& s) {
  try {
    validate(s);
  } catch (const InvalidValue& e) {
    return e.key();
  }
  return "";
}

TEST(CentrifugeScenario, DefaultK0IsJakyOfTheInstallationSet) {
  CentrifugeScenario s;
  EXPECT_EQ(s.installation_material, "original");
  EXPECT_NEAR(scenario_friction_angle_deg(s), 31.0, 1e-12);
  EXPECT_NEAR(scenario_K0(s), 1.0 - sin_deg(31.0), 1e-12);

  s.installation_material = "modified-medium-dense";
  EXPECT_NEAR(scenario_friction_angle_deg(s), 30.0, 1e-12);
  EXPECT_NEAR(scenario_K0(s), 0.5, 1e-12);  // 1 − sin 30°

  // A [[material]] table of the file: its φ_c as the reader sets it.
  s.installation_material = "my-sand";
  s.material_phi_c_deg = 33.0;
  EXPECT_NEAR(scenario_K0(s), 1.0 - sin_deg(33.0), 1e-12);
  EXPECT_NEAR(scenario_interface_friction_deg(s), 22.0, 1e-12);
}

TEST(CentrifugeScenario, InterfaceFrictionDefaultsToTwoThirdsOfTheCriticalStateAngle) {
  CentrifugeScenario s;
  EXPECT_NEAR(scenario_interface_friction_deg(s), 2.0 / 3.0 * 31.0, 1e-12);
  s.installation_material = "modified-loose";
  EXPECT_NEAR(scenario_interface_friction_deg(s), 20.0, 1e-12);
}

TEST(CentrifugeScenario, ExplicitK0AndInterfaceFrictionOverrideTheDefaults) {
  CentrifugeScenario s;
  s.K0 = 0.8;
  s.interface_friction_angle_deg = 12.5;
  EXPECT_DOUBLE_EQ(scenario_K0(s), 0.8);
  EXPECT_DOUBLE_EQ(scenario_interface_friction_deg(s), 12.5);
  // The set no longer matters.
  s.installation_material = "modified-medium-dense";
  EXPECT_DOUBLE_EQ(scenario_K0(s), 0.8);
  EXPECT_DOUBLE_EQ(scenario_interface_friction_deg(s), 12.5);
}

TEST(CentrifugeScenario, PhaseNamesFollowTheInstallationRelaxationAndLoadTest) {
  CentrifugeScenario s;
  EXPECT_EQ(scenario_phase_names(s), (std::vector<std::string>{"initial-stress", "installation",
                                                               "relaxation", "load-test"}));

  // A snapshot inside the installation splits it; the end of installation keeps its name.
  s.snapshot_depths_D = {14.7};
  EXPECT_EQ(scenario_phase_names(s),
            (std::vector<std::string>{"initial-stress", "installation-to-14.7D", "installation",
                                      "relaxation", "load-test"}));
  // Sorted; depths at or above the wished-in-place tip or at the end split nothing.
  s.snapshot_depths_D = {17.0, 5.0, 12.5, 10.0, 20.0};
  EXPECT_EQ(
      scenario_phase_names(s),
      (std::vector<std::string>{"initial-stress", "installation-to-12.5D", "installation-to-17D",
                                "installation", "relaxation", "load-test"}));

  // MPM-1: the pile wished in place and load-tested, neither installed nor relaxed.
  s.snapshot_depths_D.clear();
  s.installation_D = 0.0;
  EXPECT_EQ(scenario_phase_names(s), (std::vector<std::string>{"initial-stress", "load-test"}));

  s.installation_D = 10.0;
  s.relaxation = false;
  EXPECT_EQ(scenario_phase_names(s),
            (std::vector<std::string>{"initial-stress", "installation", "load-test"}));
  s.load_test_D = 0.0;
  EXPECT_EQ(scenario_phase_names(s), (std::vector<std::string>{"initial-stress", "installation"}));
}

TEST(CentrifugeScenario, DefaultScenarioIsValid) {
  const CentrifugeScenario s;
  EXPECT_NO_THROW(validate(s));
  EXPECT_EQ(invalid_key(s), "");
}

TEST(CentrifugeScenario, TipBelowTheFineZoneOrTheContainerIsInvalid) {
  CentrifugeScenario s;     // H = 35 D, wished in place 10 D, fine zone 4 D below the tip, 1 D more
  s.installation_D = 20.0;  // deepest tip 30 D: 30 + 4 + 1 = 35, just fits
  EXPECT_EQ(invalid_key(s), "");
  s.installation_D = 20.5;
  EXPECT_EQ(invalid_key(s), "installation.depth_D");
  s.installation_D = 30.0;  // below the container bottom
  EXPECT_EQ(invalid_key(s), "installation.depth_D");
  try {
    validate(s);
  } catch (const InvalidValue& e) {
    EXPECT_EQ(e.value(), "30");
    EXPECT_NE(e.allowed().find("20"), std::string::npos) << e.allowed();  // 35 − 10 − 4 − 1
  }
  // A deeper fine zone needs a shallower tip.
  s.installation_D = 20.0;
  s.fine_depth_below_tip_D = 4.5;
  EXPECT_EQ(invalid_key(s), "installation.depth_D");
  // A taller container makes room again.
  s.sand_height_D = 40.0;
  EXPECT_EQ(invalid_key(s), "");
}

TEST(CentrifugeScenario, ContainerMustHoldTheFineZoneAndOneDiameterMore) {
  CentrifugeScenario s;  // fine zone 3 D from the axis
  s.container_radius_D = 4.0;
  EXPECT_EQ(invalid_key(s), "");
  s.container_radius_D = 3.9;
  EXPECT_EQ(invalid_key(s), "test.container_radius_D");
  s.fine_radius_D = 2.5;
  EXPECT_EQ(invalid_key(s), "");
}

TEST(CentrifugeScenario, SnapshotDepthsMustLieOnThePathOfTheInstallation) {
  CentrifugeScenario s;  // wished in place at 10 D, installation ends at 20 D
  s.snapshot_depths_D = {10.5, 14.7, 20.0};
  EXPECT_EQ(invalid_key(s), "");
  s.snapshot_depths_D = {10.0};  // where the pile starts: it would never be written
  EXPECT_EQ(invalid_key(s), "installation.snapshot_depths_D");
  s.snapshot_depths_D = {5.0};
  EXPECT_EQ(invalid_key(s), "installation.snapshot_depths_D");
  s.snapshot_depths_D = {14.7, 20.5};
  EXPECT_EQ(invalid_key(s), "installation.snapshot_depths_D");
  s.snapshot_depths_D = {-1.0};
  EXPECT_EQ(invalid_key(s), "installation.snapshot_depths_D");
}

TEST(CentrifugeScenario, TheRunMustMoveThePile) {
  CentrifugeScenario s;
  s.installation_D = 0.0;  // MPM-1: the load test moves it
  EXPECT_EQ(invalid_key(s), "");
  s.load_test_D = 0.0;
  EXPECT_EQ(invalid_key(s), "load_test.displacement_D");
}

TEST(CentrifugeScenario, UnknownMaterialWithoutItsTableIsInvalid) {
  CentrifugeScenario s;
  s.installation_material = "no-such-set";  // and no φ_c from a [[material]] table
  EXPECT_EQ(invalid_key(s), "sand.material");
  s.material_phi_c_deg = 32.0;
  EXPECT_EQ(invalid_key(s), "");
}

TEST(CentrifugeScenario, CaseIsOnlyBuiltForValidScenarios) {
  CentrifugeScenario s;
  s.container_radius_D = 2.0;
  EXPECT_THROW(centrifuge_case(s, "mpm_case.toml"), InvalidValue);
}

TEST(CentrifugeScenario, SandDensityIsTheDryDensityOfTheVoidRatio) {
  CentrifugeScenario s;
  s.e0 = 0.68;
  EXPECT_NEAR(s.sand_density(), 2650.0 / 1.68, 1e-9);
  s.e0 = 0.8;
  EXPECT_NEAR(s.sand_density(), 2650.0 / 1.8, 1e-9);
  s.grain_density = 2700.0;
  EXPECT_NEAR(s.sand_density(), 1500.0, 1e-9);
  s.density = 1650.0;  // given: used as it is
  EXPECT_DOUBLE_EQ(s.sand_density(), 1650.0);
}

TEST(CentrifugeScenario, GeometryFollowsTheDiameter) {
  CentrifugeScenario
      s;  // docs/study.md §4: D = 11.3 mm, R = 26 D, H = 35 D, wished in place at 10 D
  EXPECT_NEAR(s.pile_radius(), 0.00565, 1e-15);
  EXPECT_NEAR(s.container_radius(), 26.0 * 0.0113, 1e-15);
  EXPECT_NEAR(s.sand_height(), 35.0 * 0.0113, 1e-15);
  EXPECT_NEAR(s.initial_tip_y(), 25.0 * 0.0113, 1e-14);
  s.wished_in_place_D = 0.0;  // the tip at the surface
  EXPECT_NEAR(s.initial_tip_y(), s.sand_height(), 1e-15);
}

}  // namespace

}  // namespace pilempm
