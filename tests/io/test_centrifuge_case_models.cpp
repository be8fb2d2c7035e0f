// Centrifuge case files with sand of any registered model and with the quasi-static analysis
// (docs/centrifuge.md): a Mohr-Coulomb or linear elastic [[material]] as the sand, read by the
// model's own reader of the registry, with its K0 and δ defaults; the keys of another model (in
// the [[material]] or in [sand]) and the MPM-4 switch with such sand as errors naming the file,
// the line and the key; [solver] analysis = "quasi-static" with displacement_step_D and
// contact_smoothing, the keys of the explicit analysis refused in it, and the typed quasi-static
// case written as mpm_case.toml reading back as the same case.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../support/centrifuge_case_texts.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_case_writer.hpp"

namespace pilempm {
namespace {

using namespace scenario;
using namespace simulation;

constexpr double kDegree = kPi / 180.0;

const std::string kMohrCoulomb = std::string("title = \"Mohr-Coulomb sand\"\n") +
                                 test_support::kMohrCoulombSandMaterial + R"([sand]
material = "mc-sand"
e0 = 0.68
[test]
container_radius_D = 6.0
sand_height_D = 12.0
[installation]
wished_in_place_D = 3.0
depth_D = 2.0
)";

const char* const kElastic = R"(title = "elastic sand"
[[material]]
name = "elastic-sand"
model = "linear-elastic"
young_modulus_MPa = 50.0
poisson_ratio = 0.25
[sand]
material = "elastic-sand"
e0 = 0.7
[pile]
interface_friction_angle_deg = 20.0
)";

// `text` with `line` inserted after the first line that starts with `after`.
std::string with_line(const std::string& text, const std::string& after, const std::string& line) {
  std::istringstream in(text);
  std::string out, current;
  bool done = false;
  while (std::getline(in, current)) {
    out += current + "\n";
    if (!done && current.rfind(after, 0) == 0) {
      out += line + "\n";
      done = true;
    }
  }
  EXPECT_TRUE(done) << after;
  return out;
}

// The 1-based number of the first line of `text` that starts with `start`.
long line_starting(const std::string& text, const std::string& start) {
  std::istringstream in(text);
  std::string current;
  for (long n = 1; std::getline(in, current); ++n)
    if (current.rfind(start, 0) == 0) return n;
  ADD_FAILURE() << "no line starts with " << start;
  return -1;
}

// The text is refused with an error at the line starting with `at` (none: no line) for `key`,
// whose message holds `reason`.
void expect_refused(const std::string& text, const std::string& at, const std::string& key,
                    const std::string& reason, std::optional<MpmAnalysis> analysis = std::nullopt) {
  try {
    (void)read_centrifuge_case_text(text, "case.toml", analysis);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "case.toml");
    EXPECT_EQ(e.key(), key) << e.what();
    if (!at.empty()) {
      EXPECT_EQ(e.line(), line_starting(text, at)) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST(CentrifugeCaseModels, MohrCoulombSandIsReadByItsModelsReaderWithItsDefaults) {
  const CentrifugeScenario s = read_centrifuge_case_text(kMohrCoulomb, "case.toml");
  EXPECT_FALSE(scenario_sand_is_hypoplastic(s));
  const MaterialSpec sand = scenario_material(s, "mc-sand");
  ASSERT_NE(sand.parameters_as<MohrCoulombParameters>(), nullptr);
  EXPECT_DOUBLE_EQ(sand.parameters_as<MohrCoulombParameters>()->young_modulus, 150e6);
  // K0 = 1 − sin φ (Jáky) and δ = 2/3 φ, with φ the Mohr-Coulomb friction angle.
  EXPECT_NEAR(scenario_K0(s), 1.0 - std::sin(33.0 * kDegree), 1e-12);
  EXPECT_NEAR(scenario_interface_friction_deg(s), 22.0, 1e-12);

  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  ASSERT_FALSE(c.regions.empty());
  for (const MpmRegion& r : c.regions) {
    EXPECT_EQ(r.material.model, "mohr-coulomb");
    EXPECT_FALSE(r.igs.has_value());  // no intergranular strain
    EXPECT_DOUBLE_EQ(r.e0, 0.68);     // the void ratio the particles carry
    EXPECT_EQ(r.e0_at, VoidRatioConvention::at_initial_stress);
    EXPECT_NEAR(r.K0, 1.0 - std::sin(33.0 * kDegree), 1e-8);
    EXPECT_NEAR(r.fill.density, 2650.0 / 1.68, 1e-5);
  }
  EXPECT_NEAR(c.bodies.at(0).friction, std::tan(22.0 * kDegree), 1e-8);
}

TEST(CentrifugeCaseModels, LinearElasticSandHasTheOedometricK0AndNeedsAnInterfaceAngle) {
  const CentrifugeScenario s = read_centrifuge_case_text(kElastic, "case.toml");
  EXPECT_NEAR(scenario_K0(s), 0.25 / 0.75, 1e-12);  // ν / (1 − ν)
  EXPECT_NEAR(scenario_interface_friction_deg(s), 20.0, 1e-12);
  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  for (const MpmRegion& r : c.regions) {
    EXPECT_EQ(r.material.model, "linear-elastic");
    EXPECT_NEAR(r.K0, 1.0 / 3.0, 1e-8);
  }
  // Without δ: elasticity has no friction angle to take 2/3 of.
  std::string without = kElastic;
  without.erase(without.find("[pile]"));
  expect_refused(without, "", "pile.interface_friction_angle_deg", "no friction angle");
}

TEST(CentrifugeCaseModels, KeysOfAnotherModelAreErrorsAtTheirLine) {
  // In the [[material]]: a hypoplastic key in a Mohr-Coulomb table, a missing key, a bad value.
  expect_refused(with_line(kMohrCoulomb, "dilatancy_angle_deg", "h_s_MPa = 4000"), "h_s_MPa",
                 "material[0].h_s_MPa", "unknown");
  std::string no_friction = kMohrCoulomb;
  no_friction.erase(no_friction.find("friction_angle_deg = 33.0\n"), 26);
  expect_refused(no_friction, "", "material[0].friction_angle_deg", "missing");
  std::string steep = kMohrCoulomb;
  steep.replace(steep.find("dilatancy_angle_deg = 5.0"), 25, "dilatancy_angle_deg = 40.0");
  expect_refused(steep, "dilatancy_angle_deg", "material[0].dilatancy_angle_deg", "33");
  // In [sand]: the intergranular strain and Bauer's scaling belong to the hypoplastic model.
  for (const char* line : {"igs = \"IGS3\"", "e0_at = \"initial-stress\""}) {
    const std::string key = std::string(line).substr(0, std::string(line).find(' '));
    expect_refused(with_line(kMohrCoulomb, "e0 = 0.68", line), key, "sand." + key,
                   "belongs to the hypoplastic model");
  }
  expect_refused(with_line(kMohrCoulomb, "e0 = 0.68", "h_s_MPa = 4000"), "h_s_MPa", "sand.h_s_MPa",
                 "unknown");
  // The MPM-4 switch replaces one hypoplastic set by another.
  expect_refused(with_line(kMohrCoulomb, "e0 = 0.68", "load_test_material = \"original\""),
                 "load_test_material", "sand.load_test_material", "mohr-coulomb");
  std::string hypoplastic = with_line(kMohrCoulomb, "e0 = 0.68",
                                      "igs = \"IGS3\"\ne0_at = \"initial-stress\"\n"
                                      "load_test_material = \"mc-sand\"");
  hypoplastic.replace(hypoplastic.find("material = \"mc-sand\""), 20, "material = \"original\"");
  expect_refused(hypoplastic, "load_test_material", "sand.load_test_material", "mohr-coulomb");
  // The void ratio is the sand's, for every model.
  std::string no_e0 = kMohrCoulomb;
  no_e0.erase(no_e0.find("e0 = 0.68\n"), 10);
  expect_refused(no_e0, "", "sand.e0", "missing");
}

std::string quasi_static(const std::string& text, const std::string& solver_lines = "") {
  return text + "[solver]\nanalysis = \"quasi-static\"\n" + solver_lines;
}

TEST(CentrifugeCaseModels, QuasiStaticAnalysisTakesTheLoadStepInDiameters) {
  const CentrifugeScenario explicit_case = read_centrifuge_case_text(kMohrCoulomb, "case.toml");
  EXPECT_EQ(explicit_case.analysis, MpmAnalysis::explicit_dynamic);  // the default
  const CentrifugeScenario s = read_centrifuge_case_text(quasi_static(kMohrCoulomb), "case.toml");
  EXPECT_EQ(s.analysis, MpmAnalysis::quasi_static);
  const MpmCase c = centrifuge_to_mpm_case(s, "mpm_case.toml");
  EXPECT_EQ(c.analysis, MpmAnalysis::quasi_static);
  EXPECT_NEAR(c.displacement_step, 0.025 * 0.0113, 1e-12);  // displacement_step_D = 0.025
  const CentrifugeScenario fine = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "displacement_step_D = 0.01\n"), "case.toml");
  EXPECT_NEAR(centrifuge_to_mpm_case(fine, "mpm_case.toml").displacement_step, 0.01 * 0.0113,
              1e-12);
  expect_refused(quasi_static(kMohrCoulomb, "displacement_step_D = 0.0\n"), "displacement_step_D",
                 "solver.displacement_step_D", "[0.0001, 1]");
  expect_refused(kMohrCoulomb + std::string("[solver]\ndisplacement_step_D = 0.05\n"),
                 "displacement_step_D", "solver.displacement_step_D", "quasi-static");
}

// The command line's --analysis: the analysis of the run whatever the file says, with the other
// analysis's defaults (the integrator) and its keys refused, the message saying where the
// analysis was chosen.
TEST(CentrifugeCaseModels, AnalysisGivenOnTheCommandLineOverridesTheFilesAndItsKeysAreChecked) {
  const CentrifugeScenario by_file = read_centrifuge_case_text(quasi_static(kMohrCoulomb), "c");
  const CentrifugeScenario s =
      read_centrifuge_case_text(kMohrCoulomb, "c", MpmAnalysis::quasi_static);
  EXPECT_EQ(s.analysis, MpmAnalysis::quasi_static);
  EXPECT_EQ(s.integrator.scheme, by_file.integrator.scheme);  // the quasi-static default
  EXPECT_NE(s.integrator.scheme, read_centrifuge_case_text(kMohrCoulomb, "c").integrator.scheme);
  EXPECT_EQ(centrifuge_mpm_case_text(centrifuge_to_mpm_case(s, "m.toml")),
            centrifuge_mpm_case_text(centrifuge_to_mpm_case(by_file, "m.toml")));
  const CentrifugeScenario back =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb), "c", MpmAnalysis::explicit_dynamic);
  EXPECT_EQ(back.analysis, MpmAnalysis::explicit_dynamic);
  // The keys of the analysis not chosen.
  expect_refused(kMohrCoulomb + std::string("[solver]\nmass_scaling = 50\n"), "mass_scaling",
                 "solver.mass_scaling", "set by --analysis", MpmAnalysis::quasi_static);
  expect_refused(quasi_static(kMohrCoulomb, "displacement_step_D = 0.05\n"), "displacement_step_D",
                 "solver.displacement_step_D", "runs analysis = \"explicit\", set by --analysis",
                 MpmAnalysis::explicit_dynamic);
  // The file's own key is still read and checked.
  expect_refused(kMohrCoulomb + std::string("[solver]\nanalysis = \"implicit\"\n"), "analysis",
                 "solver.analysis", "quasi-static", MpmAnalysis::quasi_static);
}

TEST(CentrifugeCaseModels, QuasiStaticAnalysisTakesTheContactSmoothing) {
  const CentrifugeScenario s = read_centrifuge_case_text(quasi_static(kMohrCoulomb), "case.toml");
  const double by_default =
      centrifuge_to_mpm_case(s, "mpm_case.toml").quasi_static.contact.smoothing;
  EXPECT_EQ(by_default, s.contact_smoothing);
  EXPECT_GT(by_default, 0.0);
  const CentrifugeScenario smoother = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "contact_smoothing = 0.3\n"), "case.toml");
  EXPECT_EQ(centrifuge_to_mpm_case(smoother, "mpm_case.toml").quasi_static.contact.smoothing, 0.3);
  expect_refused(quasi_static(kMohrCoulomb, "contact_smoothing = 1.5\n"), "contact_smoothing",
                 "solver.contact_smoothing", "[0, 1]");
  expect_refused(kMohrCoulomb + std::string("[solver]\ncontact_smoothing = 0.1\n"),
                 "contact_smoothing", "solver.contact_smoothing", "quasi-static");
}

// Newton's force tolerance: 1e-4 by default in a centrifuge case (not the library's 1e-6), the
// energy tolerance 100 f² with it unless given, both in the MPM case written and read back;
// refused out of range and in an explicit case.
TEST(CentrifugeCaseModels, QuasiStaticAnalysisTakesTheNewtonTolerance) {
  const CentrifugeScenario plain =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb), "case.toml");
  const simulation::MpmCase by_default = centrifuge_to_mpm_case(plain, "m.toml");
  EXPECT_EQ(by_default.quasi_static.force_tolerance, 1e-4);
  EXPECT_EQ(by_default.quasi_static.energy_tolerance, 1e-6);
  EXPECT_NE(by_default.quasi_static.force_tolerance, mpm::quasi_static::Settings{}.force_tolerance);
  const simulation::MpmCase back =
      read_mpm_case_text(centrifuge_mpm_case_text(by_default), "mpm_case.toml");
  EXPECT_EQ(back.quasi_static.force_tolerance, 1e-4);
  EXPECT_EQ(back.quasi_static.energy_tolerance, by_default.quasi_static.energy_tolerance);
  // The stall rule is on in a centrifuge case (off in the library).
  EXPECT_EQ(by_default.quasi_static.stall_iterations, 5);
  EXPECT_EQ(back.quasi_static.stall_iterations, 5);
  EXPECT_EQ(mpm::quasi_static::Settings{}.stall_iterations, 0);
  const CentrifugeScenario no_stall =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb, "stall_iterations = 0\n"), "case.toml");
  EXPECT_EQ(centrifuge_to_mpm_case(no_stall, "m.toml").quasi_static.stall_iterations, 0);
  expect_refused(quasi_static(kMohrCoulomb, "stall_iterations = -1\n"), "stall_iterations",
                 "solver.stall_iterations", "1000");
  expect_refused(kMohrCoulomb + std::string("[solver]\nstall_iterations = 5\n"), "stall_iterations",
                 "solver.stall_iterations", "quasi-static");
  // Tangent reuse: the library's default, carried to the MPM case file and back; 0 turns it off.
  EXPECT_EQ(by_default.quasi_static.tangent_reuse, mpm::quasi_static::Settings{}.tangent_reuse);
  EXPECT_EQ(back.quasi_static.tangent_reuse, by_default.quasi_static.tangent_reuse);
  const CentrifugeScenario no_reuse =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb, "tangent_reuse = 0\n"), "case.toml");
  EXPECT_EQ(centrifuge_to_mpm_case(no_reuse, "m.toml").quasi_static.tangent_reuse, 0.0);
  expect_refused(quasi_static(kMohrCoulomb, "tangent_reuse = 0.6\n"), "tangent_reuse",
                 "solver.tangent_reuse", "0.5");
  expect_refused(kMohrCoulomb + std::string("[solver]\ntangent_reuse = 0.1\n"), "tangent_reuse",
                 "solver.tangent_reuse", "quasi-static");
  // Newton's step limit: on in a centrifuge case (off in the library), carried to the MPM case
  // file and back; 0 turns it off.
  EXPECT_EQ(by_default.quasi_static.step_limit, CentrifugeScenario{}.newton_step_limit_cells);
  EXPECT_GT(by_default.quasi_static.step_limit, 0.0);
  EXPECT_EQ(mpm::quasi_static::Settings{}.step_limit, 0.0);
  EXPECT_EQ(back.quasi_static.step_limit, by_default.quasi_static.step_limit);
  const CentrifugeScenario no_limit = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "newton_step_limit_cells = 0\n"), "case.toml");
  EXPECT_EQ(centrifuge_to_mpm_case(no_limit, "m.toml").quasi_static.step_limit, 0.0);
  expect_refused(quasi_static(kMohrCoulomb, "newton_step_limit_cells = -1\n"),
                 "newton_step_limit_cells", "solver.newton_step_limit_cells", "100");
  expect_refused(kMohrCoulomb + std::string("[solver]\nnewton_step_limit_cells = 1\n"),
                 "newton_step_limit_cells", "solver.newton_step_limit_cells", "quasi-static");
  // Acceptance above the force tolerance: given in the centrifuge case, carried to the MPM case
  // file and back; 0 (never accept above the force tolerance) allowed.
  const CentrifugeScenario strict = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "force_tolerance = 1e-5\naccept_tolerance = 1e-4\n"), "case.toml");
  const simulation::MpmCase strict_case = centrifuge_to_mpm_case(strict, "m.toml");
  EXPECT_EQ(strict_case.quasi_static.accept_tolerance, 1e-4);
  EXPECT_EQ(read_mpm_case_text(centrifuge_mpm_case_text(strict_case), "mpm_case.toml")
                .quasi_static.accept_tolerance,
            1e-4);
  const CentrifugeScenario never =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb, "accept_tolerance = 0\n"), "case.toml");
  EXPECT_EQ(centrifuge_to_mpm_case(never, "m.toml").quasi_static.accept_tolerance, 0.0);
  expect_refused(quasi_static(kMohrCoulomb, "accept_tolerance = 0.2\n"), "accept_tolerance",
                 "solver.accept_tolerance", "0.1");
  expect_refused(kMohrCoulomb + std::string("[solver]\naccept_tolerance = 1e-4\n"),
                 "accept_tolerance", "solver.accept_tolerance", "quasi-static");
  const CentrifugeScenario tight = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "force_tolerance = 1e-6\n"), "case.toml");
  const simulation::MpmCase tight_case = centrifuge_to_mpm_case(tight, "m.toml");
  EXPECT_EQ(tight_case.quasi_static.force_tolerance, 1e-6);
  EXPECT_EQ(tight_case.quasi_static.energy_tolerance, 1e-10);
  const CentrifugeScenario energy = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "energy_tolerance = 1e-8\n"), "case.toml");
  const simulation::MpmCase energy_case = centrifuge_to_mpm_case(energy, "m.toml");
  EXPECT_EQ(energy_case.quasi_static.force_tolerance, 1e-4);
  EXPECT_EQ(energy_case.quasi_static.energy_tolerance, 1e-8);
  EXPECT_EQ(read_mpm_case_text(centrifuge_mpm_case_text(energy_case), "mpm_case.toml")
                .quasi_static.energy_tolerance,
            1e-8);
  expect_refused(quasi_static(kMohrCoulomb, "energy_tolerance = 0.1\n"), "energy_tolerance",
                 "solver.energy_tolerance", "0.01");
  expect_refused(kMohrCoulomb + std::string("[solver]\nenergy_tolerance = 1e-5\n"),
                 "energy_tolerance", "solver.energy_tolerance", "quasi-static");
  expect_refused(quasi_static(kMohrCoulomb, "force_tolerance = 0.01\n"), "force_tolerance",
                 "solver.force_tolerance", "0.001");
  expect_refused(kMohrCoulomb + std::string("[solver]\nforce_tolerance = 1e-5\n"),
                 "force_tolerance", "solver.force_tolerance", "quasi-static");
}

// The low-stress stabilisation: η = 3 as a last resort by default (low_stress_use),
// taken into the MPM case (and the case written from it) when set, refused out of range and in
// an explicit case.
TEST(CentrifugeCaseModels, QuasiStaticAnalysisTakesTheLowStressStabilisation) {
  const CentrifugeScenario plain =
      read_centrifuge_case_text(quasi_static(kMohrCoulomb), "case.toml");
  using mpm::quasi_static::StabilisationUse;
  EXPECT_EQ(centrifuge_to_mpm_case(plain, "m.toml").quasi_static.low_stress_stiffness, 3.0);
  EXPECT_EQ(centrifuge_to_mpm_case(plain, "m.toml").quasi_static.low_stress_use,
            StabilisationUse::last_resort);
  const CentrifugeScenario s = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb,
                   "low_stress_stiffness = 0.1\nlow_stress_pressure_Pa = 250\n"
                   "low_stress_use = \"every_step\"\n"),
      "case.toml");
  const MpmCase c = centrifuge_to_mpm_case(s, "m.toml");
  EXPECT_EQ(c.quasi_static.low_stress_stiffness, 0.1);
  EXPECT_EQ(c.quasi_static.low_stress_pressure, 250.0);
  EXPECT_EQ(c.quasi_static.low_stress_use, StabilisationUse::every_step);
  const MpmCase written = read_mpm_case_text(mpm_case_text(c), "m.toml");
  EXPECT_EQ(written.quasi_static.low_stress_stiffness, 0.1);
  EXPECT_EQ(written.quasi_static.low_stress_pressure, 250.0);
  EXPECT_EQ(written.quasi_static.low_stress_use, StabilisationUse::every_step);
  expect_refused(quasi_static(kMohrCoulomb, "low_stress_use = \"sometimes\"\n"), "low_stress_use",
                 "solver.low_stress_use", "last_resort");
  expect_refused(kMohrCoulomb + std::string("[solver]\nlow_stress_use = \"every_step\"\n"),
                 "low_stress_use", "solver.low_stress_use", "quasi-static");
  expect_refused(quasi_static(kMohrCoulomb, "low_stress_stiffness = -1\n"), "low_stress_stiffness",
                 "solver.low_stress_stiffness", "[0, 10]");
  expect_refused(quasi_static(kMohrCoulomb, "low_stress_pressure_Pa = 0\n"),
                 "low_stress_pressure_Pa", "solver.low_stress_pressure_Pa", "(0, 10000000]");
  expect_refused(kMohrCoulomb + std::string("[solver]\nlow_stress_stiffness = 0.1\n"),
                 "low_stress_stiffness", "solver.low_stress_stiffness", "quasi-static");
}

// The rate integrator: Bogacki-Shampine by default in the quasi-static analysis, Heun-Euler in the
// explicit one, and what [integrator] names in either; the MPM case written keeps it.
TEST(CentrifugeCaseModels, TheIntegratorSchemeDefaultsByAnalysis) {
  using Scheme = IntegratorSettings::Scheme;
  const auto scheme = [](const std::string& text) {
    const CentrifugeScenario s = read_centrifuge_case_text(text, "case.toml");
    const Scheme written =
        read_mpm_case_text(mpm_case_text(centrifuge_to_mpm_case(s, "m.toml")), "m.toml")
            .integrator.scheme;
    EXPECT_EQ(written, s.integrator.scheme);
    return s.integrator.scheme;
  };
  EXPECT_EQ(scheme(kMohrCoulomb), Scheme::heun_euler);
  EXPECT_EQ(scheme(quasi_static(kMohrCoulomb)), Scheme::bogacki_shampine);
  const std::string heun = "[integrator]\nscheme = \"heun-euler\"\ntolerance = 1e-4\n";
  EXPECT_EQ(scheme(quasi_static(kMohrCoulomb) + heun), Scheme::heun_euler);
  const CentrifugeScenario tighter = read_centrifuge_case_text(
      quasi_static(kMohrCoulomb) + "[integrator]\ntolerance = 1e-4\n", "case.toml");
  EXPECT_EQ(tighter.integrator.scheme, Scheme::bogacki_shampine);
  EXPECT_EQ(tighter.integrator.tolerance, 1e-4);
  EXPECT_EQ(scheme(kMohrCoulomb + "[integrator]\nscheme = \"bogacki-shampine\"\n"),
            Scheme::bogacki_shampine);
}

TEST(CentrifugeCaseModels, KeysOfTheExplicitAnalysisAreErrorsInAQuasiStaticCase) {
  for (const char* line : {"mass_scaling = 10", "courant_number = 0.5", "flip_fraction = 0.9",
                           "xpic_order = 2", "local_damping = 0.1"}) {
    const std::string key = std::string(line).substr(0, std::string(line).find(' '));
    expect_refused(quasi_static(kMohrCoulomb, std::string(line) + "\n"), key, "solver." + key,
                   "applies to analysis = \"explicit\" only");
    // The same keys are the explicit analysis's own.
    EXPECT_NO_THROW(read_centrifuge_case_text(
        kMohrCoulomb + std::string("[solver]\n") + line + "\n", "case.toml"));
  }
  expect_refused(quasi_static(kMohrCoulomb) + "[initial_stress]\nlocal_damping = 0.5\n",
                 "local_damping", "initial_stress.local_damping", "explicit");
  expect_refused(quasi_static(kMohrCoulomb) + "[relaxation]\nforce_averaging_s = 0.001\n",
                 "force_averaging_s", "relaxation.force_averaging_s", "explicit");
  // What both analyses read stays allowed (B-bar in the quasi-static one).
  EXPECT_NO_THROW(read_centrifuge_case_text(
      quasi_static(kMohrCoulomb, "threads = 1\nvolumetric_smoothing = false\n"), "case.toml"));
}

TEST(CentrifugeCaseModels, QuasiStaticCaseWrittenAsMpmCaseReadsBackAsTheSameCase) {
  const CentrifugeScenario s = read_centrifuge_case_text(
      quasi_static(kElastic, "displacement_step_D = 0.05\n"), "case.toml");
  const MpmCase typed = centrifuge_case(s, "mpm_case.toml");
  const std::string text = centrifuge_mpm_case_text(typed);
  const MpmCase read = read_mpm_case_text(text, "mpm_case.toml");
  // Written again from what was read: the same text, so every key written reads back to itself.
  EXPECT_EQ(centrifuge_mpm_case_text(read), text);
  EXPECT_EQ(read.analysis, MpmAnalysis::quasi_static);
  EXPECT_EQ(read.displacement_step, typed.displacement_step);
  EXPECT_NEAR(read.displacement_step, 0.05 * 0.0113, 1e-12);
  // The explicit analysis's settings are not written; both cases keep the library's defaults.
  for (const char* key : {"courant_number", "mass_scaling", "flip_fraction", "local_damping",
                          "stop_force_averaging_s"})
    EXPECT_EQ(text.find(key), std::string::npos) << key;
  const mpm::SolverSettings defaults{};
  for (const MpmCase* c : {&typed, &read}) {
    EXPECT_EQ(c->solver.courant_number, defaults.courant_number);
    EXPECT_EQ(c->solver.mass_scaling, defaults.mass_scaling);
    EXPECT_EQ(c->solver.local_damping, defaults.local_damping);
  }
  // What the text does not hold: the phases' damping and force averaging, the same defaults.
  ASSERT_EQ(read.phases.size(), typed.phases.size());
  for (std::size_t k = 0; k < typed.phases.size(); ++k) {
    SCOPED_TRACE(typed.phases[k].name);
    EXPECT_EQ(typed.phases[k].local_damping, read.phases[k].local_damping);
    // Relaxation ends by bisecting its load step, not on a moving average.
    EXPECT_EQ(typed.phases[k].stop_force_averaging, 0.0);
    EXPECT_EQ(read.phases[k].stop_force_averaging, 0.0);
  }
  // The K0 phase is one load step (recorded at its end).
  EXPECT_EQ(typed.phases.front().energy_interval, typed.phases.front().duration);
  ASSERT_EQ(read.regions.size(), typed.regions.size());
  for (std::size_t k = 0; k < typed.regions.size(); ++k) {
    EXPECT_EQ(read.regions[k].K0, typed.regions[k].K0);
    EXPECT_EQ(read.regions[k].e0, typed.regions[k].e0);
    EXPECT_EQ(read.regions[k].material.model, "linear-elastic");
  }
}

}  // namespace
}  // namespace pilempm
