// Centrifuge case files: the strict reader (defaults of docs/study.md §4, unknown keys and bad
// values as errors with file, line, key, value and range), the MPM case a scenario becomes (grid,
// pile, phases, materials), the particles of that case (none inside the pile wished in place, the
// geostatic stress ρ N g z) and the phase key stop_force_averaging_s with its moving average.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../support/input_texts.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/simulation/case_assembly.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/tractions.hpp"

namespace pilempm {
namespace {

using namespace simulation;
using namespace scenario;

constexpr double kDeg = kPi / 180.0;

// The smallest case file: the sand's void ratio and its convention.
const char* const kMinimal = R"([sand]
e0 = 0.68
e0_at = "initial-stress"
)";

// The built-in quick case (examples/centrifuge/quick.toml; the study layer embeds it, the io
// tests cannot reach it) on the explicit analysis (the file sets the quasi-static one; the
// geometry, particles and phases checked here are the same): R = 6 D, H = 12 D, wished in place
// at 3 D, jacked 2 D, D/4 mesh.
const char* const kQuick = R"(title = "quick case"
[test]
container_radius_D = 6.0
sand_height_D = 12.0
[sand]
material = "original"
igs = "IGS3"
e0 = 0.68
e0_at = "initial-stress"
[installation]
wished_in_place_D = 3.0
depth_D = 2.0
[mesh]
cells_per_D = 4
fine_radius_D = 2.5
fine_depth_below_tip_D = 3.0
)";

using test_support::line_of;
using test_support::replaced;

InputError centrifuge_error_of(const std::string& text) {
  return test_support::input_error_of(
      text, [&] { (void)read_centrifuge_case_text(text, "centrifuge.toml"); });
}

// Expects an InputError of centrifuge.toml at `needle`'s line (0: no line) whose message holds
// each of `parts`.
void expect_centrifuge_error(const std::string& text, const std::string& needle,
                             const std::vector<std::string>& parts) {
  const InputError e = centrifuge_error_of(text);
  EXPECT_EQ(e.file(), "centrifuge.toml") << e.what();
  const std::string message = e.what();
  if (!needle.empty()) {
    EXPECT_EQ(e.line(), line_of(text, needle)) << message;
    EXPECT_NE(message.find("centrifuge.toml:" + std::to_string(line_of(text, needle)) + ":"),
              std::string::npos)
        << message;
  }
  for (const std::string& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' in: " << message;
}

TEST(CentrifugeCase, MinimalFileGivesTheDefaultsOfTheBrief) {
  const CentrifugeScenario s = read_centrifuge_case_text(kMinimal, "centrifuge.toml");
  EXPECT_DOUBLE_EQ(s.e0, 0.68);
  EXPECT_EQ(s.e0_at, "initial-stress");
  EXPECT_NEAR(s.pile_diameter, 0.0113, 1e-15);
  EXPECT_DOUBLE_EQ(s.g_level, 40.0);
  EXPECT_DOUBLE_EQ(s.container_radius_D, 26.0);
  EXPECT_DOUBLE_EQ(s.sand_height_D, 35.0);
  EXPECT_DOUBLE_EQ(s.wished_in_place_D, 10.0);
  EXPECT_DOUBLE_EQ(s.installation_D, 10.0);
  EXPECT_TRUE(s.relaxation);
  EXPECT_GT(s.load_test_D, 0.0);
  EXPECT_EQ(s.tip, "conical");
  EXPECT_DOUBLE_EQ(s.apex_angle_deg, 60.0);
  EXPECT_EQ(s.installation_material, "original");
  EXPECT_FALSE(s.K0.has_value());
  EXPECT_FALSE(s.interface_friction_angle_deg.has_value());
  EXPECT_TRUE(s.materials.empty());
  EXPECT_EQ(scenario_phase_names(s), (std::vector<std::string>{"initial-stress", "installation",
                                                               "relaxation", "load-test"}));
}

TEST(CentrifugeCase, FileValuesAreReadInTheirUnits) {
  const std::string text = std::string(kMinimal) + R"([test]
pile_diameter_mm = 12.0
g_level = 50
[pile]
interface_friction_angle_deg = 18.0
[installation]
depth_D = 5.0
snapshot_depths_D = [12.0]
[relaxation]
enabled = false
[solver]
flip_fraction = 0.95
xpic_order = 4
)";
  const CentrifugeScenario s = read_centrifuge_case_text(text, "centrifuge.toml");
  EXPECT_NEAR(s.pile_diameter, 0.012, 1e-15);
  // The solver keys reach the generated MPM case.
  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  EXPECT_DOUBLE_EQ(c.solver.flip_fraction, 0.95);
  EXPECT_EQ(c.solver.xpic_order, 4);
  EXPECT_DOUBLE_EQ(s.g_level, 50.0);
  EXPECT_DOUBLE_EQ(scenario_interface_friction_deg(s), 18.0);
  EXPECT_DOUBLE_EQ(s.installation_D, 5.0);
  EXPECT_EQ(scenario_phase_names(s),
            (std::vector<std::string>{"initial-stress", "installation-to-12D", "installation",
                                      "load-test"}));
}

TEST(CentrifugeCase, MissingSandIsAnErrorNamingIt) {
  expect_centrifuge_error("[test]\ng_level = 40\n", "", {"sand", "e0"});
  // And [sand] without its void ratio.
  expect_centrifuge_error("[sand]\ne0_at = \"initial-stress\"\n", "", {"sand.e0", "missing"});
}

TEST(CentrifugeCase, UnknownKeyNamesTheKeyAndItsLine) {
  const std::string text = std::string(kMinimal) + "[mesh]\ncell_per_D = 8\n";
  expect_centrifuge_error(text, "cell_per_D", {"mesh.cell_per_D", "unknown"});
  // An unknown table too.
  const std::string table = std::string(kMinimal) + "[meshing]\ncells_per_D = 8\n";
  expect_centrifuge_error(table, "[meshing]", {"meshing"});
}

TEST(CentrifugeCase, OutOfRangeValueNamesTheKeyTheValueAndTheRange) {
  const std::string text = "[sand]\ne0_at = \"initial-stress\"\ne0 = -1\n";
  expect_centrifuge_error(text, "e0 = -1", {"sand.e0 = -1", "(0, 5)"});
  expect_centrifuge_error(std::string(kMinimal) + "[test]\ng_level = 0.5\n", "g_level",
                          {"test.g_level = 0.5", "[1, 1000]"});
  expect_centrifuge_error("[sand]\ne0 = 0.7\ne0_at = \"loose\"\n", "e0_at",
                          {"sand.e0_at = \"loose\"", "zero-pressure"});
  expect_centrifuge_error(std::string(kMinimal) + "[mesh]\nparticles_per_cell_outside = 0\n",
                          "particles_per_cell_outside",
                          {"mesh.particles_per_cell_outside = 0", "[1, 8]"});
}

TEST(CentrifugeCase, ValidationErrorPointsAtTheLineOfTheKey) {
  // The tip 10 + 30 D deep in 35 D of sand.
  const std::string text = std::string(kMinimal) + "[installation]\ndepth_D = 30\n";
  const InputError e = centrifuge_error_of(text);
  EXPECT_EQ(e.key(), "installation.depth_D");
  expect_centrifuge_error(text, "depth_D = 30", {"installation.depth_D = 30", "sand_height_D"});

  // The container narrower than the fine zone and one D more: at the container's line.
  const std::string narrow = std::string(kMinimal) +
                             "[test]\ng_level = 40\ncontainer_radius_D = "
                             "3.5\n[installation]\ndepth_D = 5\n";
  expect_centrifuge_error(narrow, "container_radius_D", {"test.container_radius_D = 3.5"});

  const std::string snapshots =
      std::string(kMinimal) + "[installation]\n\nsnapshot_depths_D = [12.0, 25.0]\n";
  expect_centrifuge_error(snapshots, "snapshot_depths_D",
                          {"installation.snapshot_depths_D = 25", "(10, 20]"});
}

TEST(CentrifugeCase, UnknownSandMaterialIsAnError) {
  const std::string text = "[sand]\nmaterial = \"beach\"\ne0 = 0.7\ne0_at = \"initial-stress\"\n";
  expect_centrifuge_error(text, "material", {"sand.material = \"beach\"", "original"});
  const std::string load =
      std::string(kMinimal) + "load_test_material = \"beach\"\n";  // still in [sand]
  expect_centrifuge_error(load, "load_test_material", {"sand.load_test_material = \"beach\""});
}

// A hypoplastic [[material]] of the file used as the sand.
const char* const kOwnMaterial = R"([[material]]
name = "steep-sand"
model = "hypoplastic"
base = "original"
phi_c_deg = 33.0
[sand]
material = "steep-sand"
e0 = 0.68
e0_at = "initial-stress"
[installation]
wished_in_place_D = 3.0
depth_D = 2.0
[test]
container_radius_D = 6.0
sand_height_D = 12.0
)";

TEST(CentrifugeCase, MaterialTableOfTheFileIsTheSandAndIsCopiedIntoTheMpmCase) {
  const CentrifugeScenario s = read_centrifuge_case_text(kOwnMaterial, "centrifuge.toml");
  EXPECT_EQ(s.installation_material, "steep-sand");
  EXPECT_DOUBLE_EQ(s.material_phi_c_deg, 33.0);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_NEAR(scenario_K0(s), 1.0 - std::sin(33.0 * kDeg), 1e-12);

  const std::string text = centrifuge_mpm_case_text(centrifuge_case(s, "mpm_case.toml"));
  const MpmCase c = read_mpm_case_text(text, "mpm_case.toml");
  ASSERT_EQ(c.regions.size(), 3u);  // the fine zone, beside it, below it: one set
  for (const MpmRegion& r : c.regions) EXPECT_EQ(r.material.name, "steep-sand");
  const MpmRegion& sand = c.regions[0];
  EXPECT_EQ(sand.material.name, "steep-sand");
  EXPECT_EQ(sand.material.model, "hypoplastic");
  EXPECT_FALSE(sand.material.builtin);
  EXPECT_DOUBLE_EQ(sand.material.hypoplastic().phi_c_deg, 33.0);
  // The rest of the set from its base.
  EXPECT_DOUBLE_EQ(sand.material.hypoplastic().h_s, builtin_material("original").hypoplastic().h_s);
  EXPECT_NEAR(sand.K0, 1.0 - std::sin(33.0 * kDeg), 1e-8);
  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_NEAR(c.bodies[0].friction, std::tan(22.0 * kDeg), 1e-8);  // δ = 2/3 φ_c
  ASSERT_EQ(c.models.size(), 3u);                                  // one model a region
  for (const auto& model : c.models) EXPECT_NE(model, nullptr);
}

TEST(CentrifugeCase, LoadTestMaterialAddsAMaterialChangeToTheLoadTest) {  // MPM-4
  const std::string text = std::string(kQuick) + "load_test_material = \"modified-medium-dense\"\n";
  // (appended to [mesh]: an unknown key there)
  expect_centrifuge_error(text, "load_test_material", {"mesh.load_test_material", "unknown"});

  std::string in_sand = kQuick;
  in_sand.insert(in_sand.find("e0 = 0.68"), "load_test_material = \"modified-medium-dense\"\n");
  const CentrifugeScenario s = read_centrifuge_case_text(in_sand, "centrifuge.toml");
  EXPECT_EQ(s.load_test_material, "modified-medium-dense");
  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  ASSERT_FALSE(c.phases.empty());
  const MpmPhase& load_test = c.phases.back();
  EXPECT_EQ(load_test.name, "load-test");
  ASSERT_EQ(load_test.material_changes.size(), 3u);  // every region of the sand changes
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(load_test.material_changes[k].model, static_cast<int>(k));
    EXPECT_EQ(load_test.material_changes[k].material, "modified-medium-dense");
    EXPECT_NE(load_test.material_changes[k].replacement, nullptr);
  }
  for (std::size_t k = 0; k + 1 < c.phases.size(); ++k)
    EXPECT_TRUE(c.phases[k].material_changes.empty()) << c.phases[k].name;
  // The K0 and δ stay those of the installation set.
  EXPECT_NEAR(c.regions[0].K0, 1.0 - std::sin(31.0 * kDeg), 1e-8);

  // The same set as the installation: no change.
  std::string same = kQuick;
  same.insert(same.find("e0 = 0.68"), "load_test_material = \"original\"\n");
  const MpmCase unchanged =
      centrifuge_to_mpm_case(read_centrifuge_case_text(same, "centrifuge.toml"), "mpm_case.toml");
  EXPECT_TRUE(unchanged.phases.back().material_changes.empty());
}

TEST(CentrifugeCase, BriefScenarioBecomesAnMpmCaseWithItsPhases) {
  const CentrifugeScenario s = read_centrifuge_case_text(kMinimal, "centrifuge.toml");
  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  std::vector<std::string> names;
  for (const MpmPhase& p : c.phases) names.push_back(p.name);
  EXPECT_EQ(names, scenario_phase_names(s));
  EXPECT_EQ(c.phases.front().kind, MpmPhaseKind::geostatic);
  for (const MpmPhase& p : c.phases) EXPECT_DOUBLE_EQ(p.gravity_multiplier, 40.0) << p.name;
  EXPECT_NEAR(c.x_nodes.back(), 26.0 * 0.0113, 1e-9);
  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_NEAR(c.bodies[0].tip_y, 25.0 * 0.0113, 1e-9);
  EXPECT_NEAR(c.bodies[0].radius, 0.5 * 0.0113, 1e-12);
}

// The MPM case of the quick case.
MpmCase quick_case() {
  return centrifuge_to_mpm_case(read_centrifuge_case_text(kQuick, "quick.toml"), "mpm_case.toml");
}

// The cell of `nodes` holding x.
double spacing_at(const std::vector<double>& nodes, double x) {
  const auto above = std::upper_bound(nodes.begin(), nodes.end(), x);
  EXPECT_TRUE(above != nodes.begin() && above != nodes.end()) << x;
  return *above - *(above - 1);
}

TEST(CentrifugeCase, QuickCaseIsAnAxisymmetricPileWishedInPlaceOnAGradedGrid) {
  const double D = 0.0113, H = 12.0 * D, h = D / 4.0;
  const MpmCase c = quick_case();
  EXPECT_EQ(c.geometry, mpm::Geometry::axisymmetric);
  ASSERT_EQ(c.bodies.size(), 1u);
  const MpmBody& pile = c.bodies[0];
  EXPECT_EQ(pile.name, "pile");
  EXPECT_EQ(pile.kind, MpmBodyKind::pile);
  EXPECT_NEAR(pile.radius, 0.5 * D, 1e-12);
  EXPECT_NEAR(pile.tip_y, H - 3.0 * D, 1e-9);
  EXPECT_NEAR(pile.apex_angle, 60.0 * kDeg, 1e-12);
  EXPECT_NEAR(pile.friction, std::tan(2.0 / 3.0 * 31.0 * kDeg), 1e-8);

  // The grid: from the axis to the container wall, from the container floor to above the sand;
  // the sand surface on a grid line; cells of D / 4 around the pile, its tip and below it.
  EXPECT_DOUBLE_EQ(c.x_nodes.front(), 0.0);
  EXPECT_NEAR(c.x_nodes.back(), 6.0 * D, 1e-9);
  EXPECT_DOUBLE_EQ(c.y_nodes.front(), 0.0);
  EXPECT_GT(c.y_nodes.back(), H + 2.0 * D);  // room for heave
  const double nearest_to_surface =
      *std::min_element(c.y_nodes.begin(), c.y_nodes.end(),
                        [H](double a, double b) { return std::abs(a - H) < std::abs(b - H); });
  EXPECT_NEAR(nearest_to_surface, H, 1e-9);
  for (double x : {0.1 * D, 0.6 * D, 2.0 * D}) EXPECT_NEAR(spacing_at(c.x_nodes, x), h, 1e-9) << x;
  for (double depth : {0.1 * D, 3.0 * D, 5.0 * D, 7.9 * D})  // to 3 D below the deepest tip
    EXPECT_NEAR(spacing_at(c.y_nodes, H - depth), h, 1e-9) << depth / D;
  EXPECT_NEAR(spacing_at(c.y_nodes, H + 0.5 * D), h, 1e-9);
  EXPECT_GT(spacing_at(c.x_nodes, 5.8 * D), 1.05 * h);  // graded outside the fine zone

  // The sand fills the container to H with ρ_d = 2650 / (1 + e0) at N = 40: the fine zone, the
  // sand beside it to the wall and the sand below it (one particle a cell outside the fine zone).
  ASSERT_EQ(c.regions.size(), 3u);
  for (const MpmRegion& r : c.regions) {
    EXPECT_NEAR(r.fill.density, 2650.0 / 1.68, 1e-8 * 1577.0);  // 9 digits
    EXPECT_EQ(r.initial_stress, MpmInitialStress::geostatic);
    EXPECT_NEAR(r.K0, 1.0 - std::sin(31.0 * kDeg), 1e-8);
  }
  EXPECT_NEAR(c.regions[0].fill.y_max, H, 1e-9);
  EXPECT_NEAR(c.regions[1].fill.y_max, H, 1e-9);
  EXPECT_NEAR(c.regions[1].fill.x_max, 6.0 * D, 1e-9);
  EXPECT_DOUBLE_EQ(c.regions[2].fill.y_min, 0.0);
  EXPECT_DOUBLE_EQ(c.solver.gravity, 9.81);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::bottom)], mpm::BoundaryCondition::fixed);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::right)], mpm::BoundaryCondition::roller);

  // The phases: K0 stress with the pile held, then jacked 2 D, pulled to zero force, loaded.
  std::vector<std::string> names;
  for (const MpmPhase& p : c.phases) names.push_back(p.name);
  ASSERT_EQ(names, (std::vector<std::string>{"initial-stress", "installation", "relaxation",
                                             "load-test"}));
  EXPECT_EQ(c.phases[0].kind, MpmPhaseKind::geostatic);
  EXPECT_EQ(c.phases[0].body_motion.at(0).velocity, mpm::Vec2::Zero());
  EXPECT_TRUE(c.phases[0].stop_rules.empty());
  const MpmPhase& install = c.phases[1];
  EXPECT_LT(install.body_motion.at(0).velocity.y(), 0.0);
  ASSERT_EQ(install.stop_rules.size(), 1u);
  EXPECT_EQ(install.stop_rules[0].quantity, MpmStopQuantity::displacement);
  EXPECT_NEAR(install.stop_rules[0].value, -2.0 * D, 1e-12);
  const MpmPhase& relax = c.phases[2];
  EXPECT_GT(relax.body_motion.at(0).velocity.y(), 0.0);
  EXPECT_TRUE(
      std::any_of(relax.stop_rules.begin(), relax.stop_rules.end(), [](const MpmStopRule& r) {
        return r.quantity == MpmStopQuantity::force_below && r.value == 0.0;
      }));
  EXPECT_GT(relax.stop_force_averaging, 0.0);
  const MpmPhase& load = c.phases[3];
  EXPECT_LT(load.body_motion.at(0).velocity.y(), 0.0);
  ASSERT_EQ(load.stop_rules.size(), 1u);
  EXPECT_EQ(load.stop_rules[0].quantity, MpmStopQuantity::phase_displacement);
  EXPECT_NEAR(load.stop_rules[0].value, -0.1 * D, 1e-12);
}

// Inside the quick case's pile at its initial place (conical tip, 60° apex): r < R and above
// the cone y = tip + r / tan 30°.
bool inside_quick_pile(const mpm::Vec2& x, double margin) {
  const double D = 0.0113, R = 0.5 * D, tip = 9.0 * D;
  const double r = std::abs(x.x());
  return r < R - margin && x.y() > tip + r / std::tan(30.0 * kDeg) + margin;
}

TEST(CentrifugeCase, QuickCaseParticlesStartOutsideThePileWithTheGeostaticStress) {
  const double D = 0.0113, H = 12.0 * D, R = 0.5 * D;
  const MpmCase c = quick_case();
  const mpm::Grid grid = make_mpm_grid(c);
  const mpm::Particles particles = make_mpm_particles(c, grid);

  // The same sand without the pile: those particles, less the ones inside the pile.
  MpmCase no_pile = c;
  no_pile.bodies.clear();
  const mpm::Particles all = make_mpm_particles(no_pile, grid);
  std::size_t inside = 0;
  for (const mpm::Vec2& x : all.position)
    if (inside_quick_pile(x, 0.0)) ++inside;
  EXPECT_GT(inside, 0u);
  EXPECT_EQ(particles.size() + inside, all.size());

  const mpm::RigidBody body = make_rigid_body(c.bodies[0]);
  std::size_t next_to_shaft = 0, below_tip = 0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const mpm::Vec2& x = particles.position[p];
    EXPECT_GE(body.signed_distance(x), 0.0) << x.transpose();
    EXPECT_FALSE(inside_quick_pile(x, 0.0)) << x.transpose();
    if (x.x() > R && x.x() < R + D / 4.0 && x.y() > 10.0 * D) ++next_to_shaft;
    if (x.x() < R && x.y() < 9.0 * D && x.y() > 8.5 * D) ++below_tip;
  }
  EXPECT_GT(next_to_shaft, 0u);  // the sand touches the pile
  EXPECT_GT(below_tip, 0u);

  // σ_v = ρ N g z and σ_h = K0 σ_v away from the pile.
  const double unit = 2650.0 / 1.68 * 40.0 * 9.81;  // [Pa/m]
  const double K0 = 1.0 - std::sin(31.0 * kDeg);
  int checked = 0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const mpm::Vec2& x = particles.position[p];
    const double z = H - x.y();
    if (x.x() < 2.0 * D || z < D) continue;
    const Vec6& stress = particles.state[p].stress;
    EXPECT_NEAR(-stress[k22], unit * z, 0.01 * unit * z) << x.transpose();
    EXPECT_NEAR(stress[k11], K0 * stress[k22], 1e-6 * std::abs(stress[k22])) << x.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // The whole sand is there: the mass of the container's sand less the pile's part.
  double mass = 0.0;
  for (double m : all.mass) mass += m;
  const double container = 2650.0 / 1.68 * 0.5 * std::pow(6.0 * D, 2) * H;  // per radian
  EXPECT_NEAR(mass, container, 1e-6 * container);
}

TEST(CentrifugeCase, FewerParticlesOutsideTheFineZoneFillTheSameSand) {
  const double D = 0.0113, H = 12.0 * D;
  const MpmCase c = quick_case();  // one particle a cell outside the fine zone (the default)
  std::string text = kQuick;       // two per direction everywhere: one region
  text.insert(text.find("[mesh]\n") + 7, "particles_per_cell_outside = 2\n");
  const MpmCase uniform =
      centrifuge_to_mpm_case(read_centrifuge_case_text(text, "quick.toml"), "mpm_case.toml");
  ASSERT_EQ(uniform.regions.size(), 1u);
  ASSERT_EQ(c.regions.size(), 3u);
  EXPECT_EQ(c.regions[0].fill.particles_per_cell_x, 2);
  EXPECT_EQ(c.regions[1].fill.particles_per_cell_x, 1);
  EXPECT_EQ(c.regions[2].fill.particles_per_cell_y, 1);
  EXPECT_EQ(c.x_nodes, uniform.x_nodes);  // the grid does not change
  EXPECT_EQ(c.y_nodes, uniform.y_nodes);

  // The fine zone (r < 2.5 D, down to 3 D below the deepest tip at 5 D) keeps its particles;
  // outside it each cell holds one instead of four.
  const double fine_radius = 2.5 * D, band_bottom = H - 8.0 * D;
  EXPECT_NEAR(c.regions[0].fill.x_max, fine_radius, 1e-9);
  EXPECT_NEAR(c.regions[0].fill.y_min, band_bottom, 1e-9);
  const mpm::Grid grid = make_mpm_grid(c);
  MpmCase no_pile = c, uniform_no_pile = uniform;
  no_pile.bodies.clear();
  uniform_no_pile.bodies.clear();
  const mpm::Particles fewer = make_mpm_particles(no_pile, grid);
  const mpm::Particles all = make_mpm_particles(uniform_no_pile, grid);
  auto in_fine_zone = [&](const mpm::Vec2& x) {
    return x.x() < fine_radius && x.y() > band_bottom;
  };
  std::size_t fine = 0, fine_all = 0, outside = 0, outside_all = 0;
  for (const mpm::Vec2& x : fewer.position) (in_fine_zone(x) ? fine : outside) += 1;
  for (const mpm::Vec2& x : all.position) (in_fine_zone(x) ? fine_all : outside_all) += 1;
  EXPECT_EQ(fine, fine_all);
  EXPECT_GT(outside, 0u);
  EXPECT_EQ(4 * outside, outside_all);

  // The same sand: its mass, and σ_v = ρ N g z with σ_h = K0 σ_v in every region.
  double mass = 0.0;
  for (double m : fewer.mass) mass += m;
  const double container = 2650.0 / 1.68 * 0.5 * std::pow(6.0 * D, 2) * H;  // per radian
  EXPECT_NEAR(mass, container, 1e-6 * container);
  const double unit = 2650.0 / 1.68 * 40.0 * 9.81;  // [Pa/m]
  const double K0 = 1.0 - std::sin(31.0 * kDeg);
  int beside = 0, below = 0;
  for (std::size_t p = 0; p < fewer.size(); ++p) {
    const mpm::Vec2& x = fewer.position[p];
    const double z = H - x.y();
    const Vec6& stress = fewer.state[p].stress;
    EXPECT_NEAR(-stress[k22], unit * z, 1e-6 * unit * z) << x.transpose();
    EXPECT_NEAR(stress[k11], K0 * stress[k22], 1e-6 * std::abs(stress[k22])) << x.transpose();
    if (x.x() > fine_radius) ++beside;
    if (x.y() < band_bottom && x.x() < fine_radius) ++below;
  }
  EXPECT_GT(beside, 0);
  EXPECT_GT(below, 0);
}

// --- stop_force_averaging_s ---------------------------------------------------------------

// A small axisymmetric case: a pile of radius 0.05 m (one cell) with its tip 0.1 m deep in an
// elastic ground, pushed down; line numbers refer to this text.
std::string push_case() {
  using namespace test_support;
  return "title = \"push\"\n" +
         mpm_case_opening({.geometry = "axisymmetric",
                           .x_max_m = 0.5,
                           .x_cells = 10,
                           .y_max_m = 0.7,
                           .y_cells = 14,
                           .boundaries = kRollerRightFixedBase}) +
         linear_elastic_material_text("ground", 10.0) +
         mpm_region_text({.name = "ground",
                          .x_max_m = 0.5,
                          .density_kg_per_m3 = 1600.0,
                          .material = "ground",
                          .initial_stress = "zero"}) +
         R"([[body]]
name = "pile"
kind = "pile"
radius_m = 0.05
tip_y_m = 0.4
tip = "conical"
interface_friction_angle_deg = 20.0
contact_distance_m = 0.025
[[phase]]
name = "push"
duration_s = 1.0
stop_force_y_above_N = 1e30
stop_force_averaging_s = 0.004
[phase.body.pile]
velocity_y_m_per_s = -0.2
)";
}

InputError mpm_error_of(const std::string& text) {
  return test_support::input_error_of(text, [&] { (void)read_mpm_case_text(text, "case.toml"); });
}

TEST(CentrifugeCase, StopForceAveragingGoesWithAForceStopRule) {
  const MpmCase c = read_mpm_case_text(push_case(), "case.toml");
  ASSERT_EQ(c.phases.size(), 1u);
  EXPECT_DOUBLE_EQ(c.phases[0].stop_force_averaging, 0.004);
  EXPECT_EQ(c.phases[0].stop_body, 0);
  // Without the key: the force of the last step.
  const MpmCase plain = read_mpm_case_text(
      replaced(push_case(), "stop_force_averaging_s = 0.004\n", ""), "case.toml");
  EXPECT_DOUBLE_EQ(plain.phases[0].stop_force_averaging, 0.0);
  const MpmCase below = read_mpm_case_text(
      replaced(push_case(), "stop_force_y_above_N = 1e30", "stop_force_y_below_N = 0.0"),
      "case.toml");
  EXPECT_DOUBLE_EQ(below.phases[0].stop_force_averaging, 0.004);

  // Only with a force rule (a displacement rule is not one).
  const std::string displacement =
      replaced(push_case(), "stop_force_y_above_N = 1e30", "stop_displacement_y_m = -0.05");
  InputError e = mpm_error_of(displacement);
  EXPECT_EQ(e.line(), line_of(displacement, "stop_force_averaging_s"));
  EXPECT_NE(std::string(e.what()).find("phase[0].stop_force_averaging_s"), std::string::npos)
      << e.what();
  EXPECT_NE(std::string(e.what()).find("force stop rule"), std::string::npos) << e.what();
  const std::string none = replaced(push_case(), "stop_force_y_above_N = 1e30\n", "");
  e = mpm_error_of(none);
  EXPECT_EQ(e.line(), line_of(none, "stop_force_averaging_s"));

  // Not negative.
  const std::string negative =
      replaced(push_case(), "stop_force_averaging_s = 0.004", "stop_force_averaging_s = -0.001");
  e = mpm_error_of(negative);
  EXPECT_EQ(e.line(), line_of(negative, "stop_force_averaging_s"));
  EXPECT_NE(std::string(e.what()).find("stop_force_averaging_s = -0.001"), std::string::npos)
      << e.what();
  EXPECT_NE(std::string(e.what()).find(">= 0"), std::string::npos) << e.what();
}

// The force a stop_reason() message reports ("... force y = 123.4 N"); NaN when none.
double reported_force(const std::string& reason) {
  const auto at = reason.find("force y = ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(reason.substr(at + 10));
}

TEST(CentrifugeCase, ForceStopRulesCompareTheMovingAverageOfTheForce) {
  // A rule met on every step (force below 1e30 N), so that stop_reason() reports the force it
  // compares after each step: the moving average with τ, or the last step's force without.
  const double tau = 0.004;
  const std::string text = replaced(push_case(), "stop_force_y_above_N", "stop_force_y_below_N");
  for (const bool averaged : {true, false}) {
    const MpmCase c = read_mpm_case_text(
        averaged ? text : replaced(text, "stop_force_averaging_s = 0.004\n", ""), "case.toml");
    mpm::Solver solver = make_mpm_solver(c);
    solver.set_settings(phase_settings(c, c.phases[0]));
    MpmPhaseControl push(c, 0, solver);
    push.start(mpm_traction_forces(c, solver.particles()));
    EXPECT_EQ(push.stop_reason(), "");  // no step yet: nothing to compare

    // τ df/dt = F − f with F constant over each step, from the first step's force.
    double mean = 0.0, last = 0.0, largest_lag = 0.0;
    for (int i = 0; i < 40; ++i) {
      const MpmStepPlan plan = push.plan_step(push.end_time(), solver.next_time_step());
      ASSERT_TRUE(plan.own_step);
      const double dt = solver.step();
      push.record_step(dt);
      last = 2.0 * kPi * solver.rigid_body_force(0).total.y();  // the full pile
      const double weight = averaged && i > 0 ? std::exp(-dt / tau) : 0.0;
      mean = weight * mean + (1.0 - weight) * last;
      const std::string reason = push.stop_reason();
      ASSERT_NE(reason.find("stop_force_y_below_N"), std::string::npos) << reason;
      const double reported = reported_force(reason);
      EXPECT_NEAR(reported, mean, 1e-5 * std::abs(mean) + 1e-9) << "step " << i << ": " << reason;
      largest_lag = std::max(largest_lag, std::abs(last - mean));
    }
    EXPECT_GT(last, 0.0);  // the ground pushes back on the pile pushed into it
    if (averaged) {
      EXPECT_GT(largest_lag, 0.05 * std::abs(last));  // it lags behind the rising force
    }
  }
}

}  // namespace
}  // namespace pilempm
