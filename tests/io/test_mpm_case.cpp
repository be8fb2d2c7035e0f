// MPM case files: a valid case reads into SI values; unknown keys and bad values are errors with
// the file, the line, the key, the value and the allowed range.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/files.hpp"
#include "../support/input_texts.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/simulation/case_assembly.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/tractions.hpp"

namespace pilempm {
namespace {

using namespace simulation;

// Line numbers below refer to this text (line 1 is `title`).
const char* const kCase = test_support::kMohrCoulombCase;

using test_support::line_of;
using test_support::replaced;

std::string with(const std::string& from, const std::string& to) {
  return replaced(kCase, from, to);
}

InputError error_of(const std::string& text) {
  return test_support::input_error_of(text, [&] { (void)read_mpm_case_text(text, "case.toml"); });
}

TEST(MpmCase, ValidCaseReadsIntoSiValues) {
  const MpmCase c = read_mpm_case_text(kCase, "case.toml");
  EXPECT_EQ(c.title, "test case");
  EXPECT_EQ(c.geometry, mpm::Geometry::axisymmetric);
  EXPECT_EQ(c.solver.geometry, mpm::Geometry::axisymmetric);
  EXPECT_DOUBLE_EQ(c.x_nodes.front(), 0.0);
  EXPECT_DOUBLE_EQ(c.x_nodes.back(), 2.0);
  EXPECT_NEAR(c.x_nodes[1] - c.x_nodes[0], 0.05, 1e-12);                // the fine band
  EXPECT_GT(c.x_nodes.back() - c.x_nodes[c.x_nodes.size() - 2], 0.05);  // graded outside
  ASSERT_EQ(c.y_nodes.size(), 21u);
  EXPECT_DOUBLE_EQ(c.y_nodes.front(), -1.0);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::left)], mpm::BoundaryCondition::roller);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::bottom)], mpm::BoundaryCondition::fixed);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::top)], mpm::BoundaryCondition::free);
  EXPECT_EQ(c.solver.scheme, mpm::UpdateScheme::usl);
  EXPECT_EQ(c.solver.shape_function, mpm::ShapeFunction::linear);
  EXPECT_DOUBLE_EQ(c.solver.flip_fraction, 0.95);
  EXPECT_EQ(c.solver.xpic_order, 3);
  EXPECT_DOUBLE_EQ(c.solver.courant_number, 0.4);

  ASSERT_EQ(c.regions.size(), 1u);
  const MpmRegion& r = c.regions[0];
  EXPECT_EQ(r.material.model, "mohr-coulomb");
  EXPECT_DOUBLE_EQ(r.material.parameters_as<MohrCoulombParameters>()->young_modulus,
                   50.0e6);  // MPa -> Pa
  EXPECT_DOUBLE_EQ(r.material.parameters_as<MohrCoulombParameters>()->cohesion,
                   1.0e3);  // kPa -> Pa
  EXPECT_EQ(r.fill.particles_per_cell_x, 2);
  EXPECT_EQ(r.fill.particles_per_cell_y, 3);
  EXPECT_DOUBLE_EQ(r.fill.density, 1800.0);
  EXPECT_EQ(r.initial_stress, MpmInitialStress::geostatic);
  EXPECT_NEAR(r.K0, 0.5, 1e-12);  // Jáky's 1 - sin 30° by default
  EXPECT_DOUBLE_EQ(r.e0, 0.7);
  ASSERT_EQ(c.models.size(), 1u);

  ASSERT_EQ(c.phases.size(), 2u);
  EXPECT_EQ(c.phases[0].name, "equilibrium");
  EXPECT_DOUBLE_EQ(c.phases[0].gravity_multiplier, 10.0);  // from [solver]
  EXPECT_DOUBLE_EQ(c.phases[0].local_damping, 0.2);
  EXPECT_DOUBLE_EQ(c.phases[0].output_interval, 0.1);
  EXPECT_DOUBLE_EQ(c.phases[1].duration, 2.0);
  EXPECT_DOUBLE_EQ(c.phases[1].gravity_multiplier, 20.0);
  EXPECT_DOUBLE_EQ(c.phases[1].output_interval, 2.0);  // default: the phase's duration
}

TEST(MpmCase, GeostaticStressUsesTheFirstPhaseGravity) {
  const MpmCase c = read_mpm_case_text(kCase, "case.toml");
  const mpm::Grid grid = make_mpm_grid(c);
  const mpm::Particles particles = make_mpm_particles(c, grid);
  ASSERT_GT(particles.size(), 0u);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double depth = 0.5 - particles.position[p].y();
    const double vertical = 1800.0 * 9.81 * 10.0 * depth;
    EXPECT_NEAR(particles.state[p].stress[k22], -vertical, 1e-9 * vertical + 1e-9);
    EXPECT_NEAR(particles.state[p].stress[k11], -0.5 * vertical, 1e-9 * vertical + 1e-9);
    EXPECT_NEAR(particles.state[p].stress[k33], -0.5 * vertical, 1e-9 * vertical + 1e-9);
    EXPECT_DOUBLE_EQ(particles.state[p].void_ratio, 0.7);
  }
}

TEST(MpmCase, UnknownKeyIsAnErrorWithFileLineAndKey) {
  const InputError e = error_of(with("courant_number = 0.4", "courant_numbr = 0.4"));
  EXPECT_EQ(e.file(), "case.toml");
  EXPECT_EQ(e.line(), 27);
  EXPECT_NE(e.key().find("courant_numbr"), std::string::npos) << e.what();
  const std::string message = e.what();
  EXPECT_NE(message.find("case.toml:27"), std::string::npos) << message;
  EXPECT_NE(message.find("courant_number"), std::string::npos) << message;  // the guess

  const InputError region = error_of(with("density_kg_per_m3", "density_kg_m3"));
  EXPECT_EQ(region.line(), 45);
  EXPECT_NE(std::string(region.what()).find("region"), std::string::npos) << region.what();
}

TEST(MpmCase, BadValueNamesTheValueAndTheRange) {
  const InputError damping = error_of(with("local_damping = 0.2", "local_damping = 1.5"));
  EXPECT_EQ(damping.line(), 26);
  std::string message = damping.what();
  EXPECT_NE(message.find("solver.local_damping"), std::string::npos) << message;
  EXPECT_NE(message.find("1.5"), std::string::npos) << message;
  EXPECT_NE(message.find("[0, 1)"), std::string::npos) << message;

  const InputError kind = error_of(with("\"axisymmetric\"", "\"3d\""));
  message = kind.what();
  EXPECT_EQ(kind.line(), 3);
  EXPECT_NE(message.find("plane-strain"), std::string::npos) << message;

  const InputError duration = error_of(with("duration_s = 0.5", "duration_s = -1"));
  message = duration.what();
  EXPECT_NE(message.find("phase[0].duration_s"), std::string::npos) << message;
  EXPECT_NE(message.find("> 0"), std::string::npos) << message;

  const InputError material = error_of(with("material = \"sand\"", "material = \"clay\""));
  EXPECT_NE(std::string(material.what()).find("unknown"), std::string::npos) << material.what();

  // The axis of an axisymmetric grid must be at r = 0.
  const InputError axis = error_of(with("min_m = 0.0\nmax_m = 2.0\nband_min_m = 0.0",
                                        "min_m = 0.1\nmax_m = 2.0\nband_min_m = 0.1"));
  EXPECT_NE(std::string(axis.what()).find("axis"), std::string::npos) << axis.what();
}

// [solver] contact: "nodes" (the default) or "surface" (the corner penalty contact).
TEST(MpmCase, ContactSchemeIsNodesOrSurfaceWithFileLineAndAllowedValues) {
  EXPECT_EQ(read_mpm_case_text(kCase, "case.toml").solver.contact, mpm::ContactScheme::nodes);
  const std::string surface =
      with("local_damping = 0.2", "local_damping = 0.2\ncontact = \"surface\"");
  EXPECT_EQ(read_mpm_case_text(surface, "case.toml").solver.contact, mpm::ContactScheme::surface);
  const InputError e =
      error_of(with("local_damping = 0.2", "local_damping = 0.2\ncontact = \"edges\""));
  EXPECT_EQ(e.file(), "case.toml");
  EXPECT_EQ(e.line(), 27);
  const std::string message = e.what();
  EXPECT_NE(message.find("contact"), std::string::npos) << message;
  EXPECT_NE(message.find("edges"), std::string::npos) << message;
  EXPECT_NE(message.find("nodes"), std::string::npos) << message;
  EXPECT_NE(message.find("surface"), std::string::npos) << message;
}

TEST(MpmCase, MissingPhaseIsAnError) {
  std::string text = kCase;
  text = text.substr(0, text.find("[[phase]]"));
  const InputError e = error_of(text);
  EXPECT_NE(std::string(e.what()).find("[[phase]]"), std::string::npos) << e.what();
}

// A hypoplastic ground with intergranular strain in axisymmetry: e0 given at zero pressure is
// scaled to each particle's geostatic mean stress by Bauer's law, the IGS starts fully mobilised,
// and a short run writes igs_rho and the per-radian energy header.
std::string hypoplastic_case() {
  using namespace test_support;
  return mpm_case_opening(
             {.geometry = "axisymmetric",
              .x_max_m = 0.4,
              .x_cells = 4,
              .y_max_m = 0.6,
              .y_cells = 6,
              .boundaries = kRollerRightFixedBase,
              .solver = "gravity_multiplier = 50.0\nlocal_damping = 0.5\nthreads = 1\n"}) +
         mpm_region_text({.x_max_m = 0.4, .density_kg_per_m3 = 1600.0, .material = "original"}) +
         R"(igs = "IGS1"
e0 = 0.9
e0_at = "zero-pressure"
[[phase]]
duration_s = 0.002
output_interval_s = 0.001
)";
}

TEST(MpmCase, HypoplasticGroundStartsAtItsScaledVoidRatioAndRuns) {
  const MpmCase c = read_mpm_case_text(hypoplastic_case(), "hypo.toml");
  const MpmRegion& r = c.regions.at(0);
  EXPECT_EQ(r.material.model, "hypoplastic");
  EXPECT_NEAR(r.K0, 1.0 - std::sin(r.material.hypoplastic().phi_c_deg * kPi / 180.0), 1e-12);
  const mpm::Grid grid = make_mpm_grid(c);
  EXPECT_TRUE(grid.axis_of_symmetry());
  const mpm::Particles particles = make_mpm_particles(c, grid);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const MaterialState& s = particles.state[p];
    const double mean = mean_stress(s.stress);
    EXPECT_NEAR(s.void_ratio,
                initial_void_ratio(r.material.hypoplastic(), 0.9,
                                   VoidRatioConvention::at_zero_pressure, mean),
                1e-12);
    EXPECT_LT(s.void_ratio, 0.9);
    EXPECT_GT(Hypoplastic::intergranular_strain(s).norm(), 0.0);
  }

  const std::filesystem::path out = test_support::fresh_temp_path("mpm-hypo");
  const MpmRunSummary summary = run_mpm_case(c, out, nullptr);
  EXPECT_NEAR(summary.time, 0.002, 1e-12);
  ASSERT_EQ(summary.vtu_files.size(), 3u);  // t = 0, 0.001, 0.002
  const std::string vtu = test_support::read_text(summary.vtu_files.back());
  EXPECT_NE(vtu.find("Name=\"igs_rho\""), std::string::npos);
  std::ifstream csv(summary.energies_file);
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("per radian"), std::string::npos) << header;
  std::filesystem::remove_all(out);
}

TEST(MpmCase, PhaseMaterialsSwitchHypoplasticSetsAndKeepTheRegionsIgs) {
  std::string text = hypoplastic_case();
  text +=
      "[[phase]]\nduration_s = 0.001\n[phase.materials]\noriginal = \"modified-medium-dense\"\n";
  const MpmCase c = read_mpm_case_text(text, "hypo.toml");
  ASSERT_EQ(c.phases.size(), 2u);
  ASSERT_EQ(c.phases[1].material_changes.size(), 1u);
  const auto* before = dynamic_cast<const Hypoplastic*>(c.models.at(0).get());
  const auto* after =
      dynamic_cast<const Hypoplastic*>(c.phases[1].material_changes[0].replacement.get());
  ASSERT_NE(before, nullptr);
  ASSERT_NE(after, nullptr);
  EXPECT_DOUBLE_EQ(before->parameters().alpha, 0.12);
  EXPECT_DOUBLE_EQ(after->parameters().alpha, 0.03);
  EXPECT_TRUE(after->intergranular().enabled());  // the region's igs = "IGS1"
  EXPECT_DOUBLE_EQ(after->intergranular().R, before->intergranular().R);
}

TEST(MpmCase, RegionOutsideTheGridIsAnError) {
  const InputError e = error_of(with("y_max_m = 0.5", "y_max_m = 1.5"));
  const std::string message = e.what();
  EXPECT_NE(message.find("region[0].y_max_m = 1.5"), std::string::npos) << message;
  EXPECT_NE(message.find("(-1, 1]"), std::string::npos) << message;
}

using test_support::pile_case;

// Expects an InputError at `needle`'s line whose message holds each of `parts`.
void expect_error(const std::string& text, const std::string& needle,
                  const std::vector<std::string>& parts) {
  const InputError e = error_of(text);
  EXPECT_EQ(e.file(), "case.toml");
  EXPECT_EQ(e.line(), line_of(text, needle)) << e.what();
  const std::string message = e.what();
  EXPECT_NE(message.find("case.toml:" + std::to_string(e.line())), std::string::npos) << message;
  for (const std::string& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' in: " << message;
}

TEST(MpmCase, PileCaseReadsBodiesMotionsStopRulesMaterialsAndLoads) {
  const MpmCase c = read_mpm_case_text(pile_case(), "case.toml");
  ASSERT_EQ(c.bodies.size(), 1u);
  const MpmBody& b = c.bodies[0];
  EXPECT_EQ(b.name, "pile");
  EXPECT_EQ(b.kind, MpmBodyKind::pile);
  EXPECT_DOUBLE_EQ(b.radius, 0.01);
  EXPECT_DOUBLE_EQ(b.tip_y, 0.4);
  EXPECT_NEAR(b.apex_angle, kPi / 3.0, 1e-15);  // 60° by default
  EXPECT_NEAR(b.friction, std::tan(20.0 * kPi / 180.0), 1e-15);
  EXPECT_DOUBLE_EQ(b.contact_distance, 0.01);

  ASSERT_EQ(c.solver.absorbing_boundaries.size(), 1u);
  const mpm::AbsorbingBoundary& a = c.solver.absorbing_boundaries[0];
  EXPECT_EQ(a.side, mpm::Side::right);
  EXPECT_DOUBLE_EQ(a.density, 1600.0);
  EXPECT_DOUBLE_EQ(a.p_wave_speed, 300.0);
  EXPECT_DOUBLE_EQ(a.s_wave_speed, 150.0);
  EXPECT_EQ(c.boundaries[static_cast<int>(mpm::Side::right)], mpm::BoundaryCondition::free);
  EXPECT_TRUE(c.solver.volumetric_smoothing);
  EXPECT_TRUE(phase_settings(c, c.phases[1]).volumetric_smoothing);

  ASSERT_EQ(c.tractions.size(), 1u);
  EXPECT_EQ(c.tractions[0].region, 0);
  EXPECT_EQ(c.tractions[0].side, mpm::Side::top);
  EXPECT_DOUBLE_EQ(c.tractions[0].normal, 10.0e3);
  EXPECT_DOUBLE_EQ(c.tractions[0].shear, 1.0e3);

  ASSERT_EQ(c.phases.size(), 3u);
  const MpmPhase& geostatic = c.phases[0];
  EXPECT_EQ(geostatic.kind, MpmPhaseKind::geostatic);
  EXPECT_DOUBLE_EQ(geostatic.traction_multiplier, 0.5);
  EXPECT_TRUE(geostatic.checkpoint);
  ASSERT_EQ(geostatic.body_motion.size(), 1u);
  EXPECT_EQ(geostatic.body_motion[0].velocity, mpm::Vec2::Zero());  // held still
  EXPECT_TRUE(geostatic.stop_rules.empty());
  EXPECT_EQ(geostatic.stop_body, -1);

  const MpmPhase& install = c.phases[1];
  EXPECT_EQ(install.kind, MpmPhaseKind::standard);
  EXPECT_FALSE(install.checkpoint);
  EXPECT_DOUBLE_EQ(install.traction_multiplier, 1.0);
  EXPECT_DOUBLE_EQ(install.body_motion[0].velocity.y(), -0.1);
  EXPECT_DOUBLE_EQ(install.body_motion[0].ramp, 0.01);
  EXPECT_EQ(install.stop_body, 0);  // the only body
  ASSERT_EQ(install.stop_rules.size(), 1u);
  EXPECT_EQ(install.stop_rules[0].key, "stop_displacement_y_m");
  EXPECT_EQ(install.stop_rules[0].quantity, MpmStopQuantity::displacement);
  EXPECT_EQ(install.stop_rules[0].component, 1);
  EXPECT_DOUBLE_EQ(install.stop_rules[0].value, -0.05);
  ASSERT_EQ(install.material_changes.size(), 1u);
  EXPECT_EQ(install.material_changes[0].model, 0);
  EXPECT_EQ(install.material_changes[0].material, "soft-sand");
  ASSERT_NE(install.material_changes[0].replacement, nullptr);

  const MpmPhase& relax = c.phases[2];
  ASSERT_EQ(relax.stop_rules.size(), 2u);
  EXPECT_EQ(relax.stop_rules[0].quantity, MpmStopQuantity::phase_displacement);
  EXPECT_DOUBLE_EQ(relax.stop_rules[0].value, 0.01);
  EXPECT_EQ(relax.stop_rules[1].quantity, MpmStopQuantity::force_below);
  EXPECT_DOUBLE_EQ(relax.stop_rules[1].value, 0.0);
  EXPECT_TRUE(relax.material_changes.empty());

  // The solver gets the pile, at rest where the case puts it.
  mpm::Solver solver = make_mpm_solver(c);
  ASSERT_EQ(solver.rigid_body_count(), 1);
  EXPECT_NEAR(solver.rigid_body(0).signed_distance({0.0, 0.5}), -0.01, 1e-12);  // in the shaft
  EXPECT_NEAR(solver.rigid_body(0).signed_distance({0.0, 0.3}), 0.1, 1e-12);    // below the tip
  EXPECT_NEAR(solver.rigid_body(0).friction(), b.friction, 1e-15);
  EXPECT_EQ(solver.rigid_body(0).part_names().at(0), "tip");
}

TEST(MpmCase, BodyKeysAreCheckedWithLineKeyValueAndRange) {
  const std::string pile = pile_case();
  expect_error(
      replaced(pile, "interface_friction_angle_deg = 20.0", "interface_friction_angle_deg = 90.0"),
      "interface_friction_angle_deg", {"body[0].interface_friction_angle_deg = 90:", "[0, 90)"});
  expect_error(replaced(pile, "tip = \"conical\"", "tip = \"round\""),
               "tip = ", {"body[0].tip = \"round\"", "conical", "flat"});
  expect_error(replaced(pile, "tip = \"conical\"", "tip = \"conical\"\napex_angle_deg = 180"),
               "apex_angle_deg", {"body[0].apex_angle_deg = 180", "(0, 180)"});
  expect_error(replaced(pile, "tip = \"conical\"", "tip = \"flat\"\napex_angle_deg = 90"),
               "apex_angle_deg", {"apex_angle_deg", "flat tip"});
  expect_error(replaced(pile, "radius_m = 0.01", "radius_m = 0.0"), "radius_m",
               {"body[0].radius_m = 0:", "> 0"});
  expect_error(replaced(pile, "contact_distance_m = 0.01", "contact_distanc_m = 0.01"),
               "contact_distanc_m", {"contact_distance_m"});
  expect_error(replaced(pile, "kind = \"pile\"", "kind = \"polygon\""), "kind = \"polygon\"",
               {"body[0].kind", "axisymmetry"});
  const std::string second_body =
      "[[body]]\nname = \"pile\"  # again\nkind = \"pile\"\nradius_m = 0.02\ntip_y_m = 0.4\n"
      "tip = \"flat\"\ninterface_friction_angle_deg = 20.0\n[[traction]]";
  expect_error(replaced(pile, "[[traction]]", second_body), "# again",
               {"body[1].name = \"pile\"", "distinct"});

  // Polygons belong to plane strain, with at least three convex corners.
  const std::string plane =
      replaced(replaced(pile_case(), "kind = \"axisymmetric\"", "kind = \"plane-strain\""),
               "kind = \"pile\"\nradius_m = 0.01\ntip_y_m = 0.4\ntip = \"conical\"",
               "kind = \"polygon\"\nvertices_m = [[0.0, 0.5], [0.1, 0.5], [0.1, 0.6]]");
  const std::string polygon_case = replaced(plane, "[phase.body.pile]\nvelocity_y_m_per_s = -0.1",
                                            "[phase.body.pile]\nvelocity_x_m_per_s = 0.1");
  const MpmCase c = read_mpm_case_text(polygon_case, "case.toml");
  ASSERT_EQ(c.bodies.at(0).vertices.size(), 3u);
  EXPECT_DOUBLE_EQ(c.bodies[0].vertices[2].y(), 0.6);
  EXPECT_DOUBLE_EQ(c.phases[1].body_motion[0].velocity.x(), 0.1);  // a polygon may move sideways
  expect_error(replaced(plane, "[[0.0, 0.5], [0.1, 0.5], [0.1, 0.6]]", "[[0.0, 0.5], [0.1, 0.5]]"),
               "vertices_m", {"body[0].vertices_m", "at least three"});
  expect_error(replaced(plane, "[[0.0, 0.5], [0.1, 0.5], [0.1, 0.6]]",
                        "[[0.0, 0.5], [0.1, 0.5], [0.1, \"a\"]]"),
               "vertices_m", {"body[0].vertices_m", "finite numbers"});
  expect_error(replaced(plane, "[[0.0, 0.5], [0.1, 0.5], [0.1, 0.6]]",
                        "[[0.0, 0.0], [0.2, 0.0], [0.1, 0.05], [0.2, 0.2], [0.0, 0.2]]"),
               "vertices_m", {"body[0].vertices_m", "not a valid body"});
  expect_error(replaced(plane, "kind = \"polygon\"", "kind = \"pile\""), "kind = \"pile\"",
               {"body[0].kind", "plane strain"});
}

TEST(MpmCase, PhaseKeysAreCheckedWithLineKeyValueAndRange) {
  const std::string pile = pile_case();
  expect_error(replaced(pile, "[phase.body.pile]\nvelocity_y_m_per_s = -0.1",
                        "[phase.body.pile]\nvelocity_y_m_per_s = -0.1\n[phase.body.pipe]\n"
                        "velocity_y_m_per_s = -0.1"),
               "[phase.body.pipe]", {"phase[1].body.pipe", "unknown body", "\"pile\""});
  expect_error(replaced(pile, "velocity_y_m_per_s = -0.1", "velocity_x_m_per_s = -0.1"),
               "velocity_x_m_per_s", {"phase[1].body.pile.velocity_x_m_per_s", "axis"});
  expect_error(replaced(pile, "ramp_s = 0.01", "ramp_s = -0.01"), "ramp_s",
               {"phase[1].body.pile.ramp_s = -0.01", ">= 0"});
  expect_error(replaced(pile, "ramp_s = 0.01", "ramp = 0.01"), "ramp = ", {"ramp_s"});
  expect_error(replaced(pile, "stop_displacement_y_m = -0.05", "stop_displacement_x_m = -0.05"),
               "stop_displacement_x_m", {"phase[1].stop_displacement_x_m", "pile"});
  expect_error(replaced(pile, "stop_displacement_y_m = -0.05",
                        "stop_displacement_y_m = -0.05\nstop_body = \"pipe\""),
               "stop_body", {"phase[1].stop_body = \"pipe\"", "unknown body"});
  expect_error(
      replaced(pile, "stop_phase_displacement_y_m = 0.01", "stop_phase_displacement_y_m = 0.0"),
      "stop_phase_displacement_y_m", {"phase[2].stop_phase_displacement_y_m = 0:", "non-zero"});
  expect_error(replaced(pile, "stop_force_y_below_N = 0.0", "stop_force_y_below_N = \"zero\""),
               "stop_force_y_below_N", {"phase[2].stop_force_y_below_N", "a number"});
  expect_error(replaced(pile, "stop_force_y_below_N = 0.0", "stop_force_y_under_N = 0.0"),
               "stop_force_y_under_N", {"stop_force_y_under_N", "unknown"});
  expect_error(replaced(pile, "traction_multiplier = 0.5", "traction_multiplier = \"half\""),
               "traction_multiplier", {"phase[0].traction_multiplier"});
  expect_error(replaced(pile, "checkpoint = false", "checkpoint = 0"), "checkpoint = 0",
               {"phase[1].checkpoint"});
  expect_error(replaced(pile, "kind = \"geostatic\"", "kind = \"static\""), "\"static\"",
               {"phase[0].kind = \"static\"", "standard", "geostatic"});
  expect_error(replaced(pile, "initial_stress = \"geostatic\"", "initial_stress = \"zero\""),
               "kind = \"geostatic\"", {"phase[0].kind", "initial_stress"});

  // Without bodies, no stop rule and no body motion.
  const auto no_body_start = pile.find("[[body]]");
  const auto no_body_end = pile.find("[[traction]]");
  std::string no_body = pile;
  no_body.erase(no_body_start, no_body_end - no_body_start);
  expect_error(
      replaced(no_body, "[phase.body.pile]\nvelocity_y_m_per_s = -0.1\nramp_s = 0.01\n", ""),
      "stop_displacement_y_m", {"phase[1].stop_displacement_y_m", "[[body]]"});

  // Material changes: a role the regions use, a known set of the same kind.
  expect_error(replaced(pile, "sand = \"soft-sand\"", "clay = \"soft-sand\""),
               "clay =", {"phase[1].materials.clay", "unknown", "\"sand\""});
  expect_error(replaced(pile, "sand = \"soft-sand\"", "sand = \"softer-sand\""), "sand = \"softer",
               {"phase[1].materials.sand = \"softer-sand\"", "unknown", "soft-sand"});
  expect_error(replaced(pile, "sand = \"soft-sand\"", "sand = \"elastic\""), "sand = \"elastic\"",
               {"phase[1].materials.sand = \"elastic\"", "mohr-coulomb"});
}

TEST(MpmCase, LoadAndBoundaryKeysAreCheckedWithLineKeyValueAndRange) {
  const std::string pile = pile_case();
  expect_error(replaced(pile, "region = \"ground\"", "region = \"earth\""), "region = \"earth\"",
               {"traction[0].region = \"earth\"", "\"ground\""});
  expect_error(replaced(pile, "side = \"top\"", "side = \"up\""), "side = \"up\"",
               {"traction[0].side = \"up\"", "left", "top"});
  expect_error(replaced(pile, "normal_kPa = 10.0", "normal_kPa = \"ten\""), "normal_kPa",
               {"traction[0].normal_kPa", "a number"});
  expect_error(replaced(pile, "normal_kPa = 10.0", "normal_kPa = 10.0\npressure_kPa = 10.0"),
               "pressure_kPa", {"traction[0].pressure_kPa", "unknown"});
  expect_error(
      replaced(pile, "density_kg_per_m3 = 1600.0, p_wave", "density_kg_per_m3 = -1.0, p_wave"),
      "right = {", {"boundaries.right.density_kg_per_m3 = -1:", "> 0"});
  expect_error(replaced(pile, "s_wave_speed_m_per_s = 150.0", "s_speed_m_per_s = 150.0"),
               "right = {", {"s_wave_speed_m_per_s"});
  expect_error(replaced(pile, "kind = \"absorbing\"", "kind = \"viscous\""), "right = {",
               {"boundaries.right.kind = \"viscous\"", "absorbing"});
  expect_error(replaced(pile, "bottom = \"fixed\"", "bottom = \"absorbing\""),
               "bottom =", {"boundaries.bottom = \"absorbing\"", "roller"});
  expect_error(replaced(pile, "volumetric_smoothing = true", "volumetric_smoothing = 1"),
               "volumetric_smoothing", {"solver.volumetric_smoothing"});
}

TEST(MpmCase, GeostaticStateIsResetUnderTheGivenGravity) {
  const MpmCase c = read_mpm_case_text(pile_case(), "case.toml");
  mpm::Solver solver = make_mpm_solver(c);
  mpm::Particles& particles = solver.particles();
  ASSERT_GT(particles.size(), 0u);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    particles.state[p].stress = Vec6::Zero();
    particles.velocity[p] = {0.1, 0.2};
  }
  set_geostatic_state(c, solver, 3.0 * 9.81);
  const double K0 = 0.5;  // 1 - sin 30°
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double vertical = 1600.0 * 3.0 * 9.81 * (0.5 - particles.position[p].y());
    EXPECT_NEAR(particles.state[p].stress[k22], -vertical, 1e-9 * vertical);
    EXPECT_NEAR(particles.state[p].stress[k11], -K0 * vertical, 1e-9 * vertical);
    EXPECT_NEAR(particles.state[p].stress[k33], -K0 * vertical, 1e-9 * vertical);
    EXPECT_EQ(particles.velocity[p], mpm::Vec2::Zero());
  }
}

// A column under self-weight and a surcharge on its top, started by a geostatic phase; a second
// phase switches to a stiffer set.
std::string surcharge_case() {
  using namespace test_support;
  return mpm_case_opening({.x_max_m = 0.5, .x_cells = 5, .y_max_m = 1.2, .y_cells = 12}) +
         linear_elastic_material_text("soft", 20.0) + linear_elastic_material_text("stiff", 40.0) +
         mpm_region_text({.name = "column", .x_max_m = 0.5, .y_max_m = 1.0, .material = "soft"}) +
         R"([[traction]]
region = "column"
side = "top"
normal_kPa = 10.0
[[phase]]
name = "settle"
kind = "geostatic"
duration_s = 0.5
local_damping = 0.7
gravity_multiplier = 2.0
traction_multiplier = 2.0
[[phase]]
name = "stiffer"
duration_s = 0.01
[phase.materials]
soft = "stiff"
)";
}

TEST(MpmCase, PhaseStartSetsTractionsGeostaticStressAndMaterials) {
  const MpmCase c = read_mpm_case_text(surcharge_case(), "case.toml");
  mpm::Solver solver = make_mpm_solver(c);
  const std::vector<mpm::Vec2> forces = mpm_traction_forces(c, solver.particles());
  mpm::Vec2 total = mpm::Vec2::Zero();
  for (const mpm::Vec2& f : forces) total += f;
  EXPECT_NEAR(total.y(), -10e3 * 0.5, 1e-6);  // 10 kPa on 0.5 m

  // The geostatic phase: stress from N = 2 (also at t = 0: the first phase's N), loads × 2.
  for (mpm::Vec2& v : solver.particles().velocity) v = {0.0, -1.0};
  solver.set_settings(phase_settings(c, c.phases[0]));
  MpmPhaseControl settle(c, 0, solver);
  settle.start(forces);
  const double K0 = 0.3 / 0.7;
  const mpm::Particles& particles = solver.particles();
  for (std::size_t p = 0; p < particles.size(); ++p) {
    EXPECT_EQ(particles.external_force[p], 2.0 * forces[p]);
    EXPECT_EQ(particles.velocity[p], mpm::Vec2::Zero());
    const double vertical = 2000.0 * 2.0 * 9.81 * (1.0 - particles.position[p].y());
    EXPECT_NEAR(particles.state[p].stress[k22], -vertical, 1e-9 * vertical);
    EXPECT_NEAR(particles.state[p].stress[k11], -K0 * vertical, 1e-9 * vertical);
  }
  solver.run_until(settle.end_time());
  // At rest under weight and surcharge: σ_yy = N ρ g (H - y) + 2 × 10 kPa below the top cell
  // (the cell of the loaded particles carries part of the load only: point loads at the
  // particles, not at the surface).
  int checked = 0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (particles.position[p].y() > 0.9) continue;
    ++checked;
    const double expected = 2000.0 * 2.0 * 9.81 * (1.0 - particles.position[p].y()) + 20e3;
    EXPECT_NEAR(-particles.state[p].stress[k22], expected, 0.03 * expected) << p;
  }
  EXPECT_EQ(checked, 180);

  // The next phase: the stiffer set, the stresses kept.
  const Vec6 before = particles.state[0].stress;
  const ConstitutiveModel* soft = solver.materials()[0].get();
  solver.set_settings(phase_settings(c, c.phases[1]));
  MpmPhaseControl stiffer(c, 1, solver);
  stiffer.start(forces);
  EXPECT_NE(solver.materials()[0].get(), soft);
  EXPECT_EQ(solver.materials()[0], c.phases[1].material_changes.at(0).replacement);
  EXPECT_EQ(particles.state[0].stress, before);
  EXPECT_EQ(particles.external_force[0], forces[0]);  // multiplier 1
  EXPECT_EQ(stiffer.stop_reason(), "");
}

TEST(MpmCase, AbsorbingSideTakesEnergyOutOfAMovingBlock) {
  // A block moving towards the right side, which absorbs: energies.csv shows absorbed_J > 0.
  std::string text = surcharge_case();
  text = replaced(text, "right = \"roller\"",
                  "right = { kind = \"absorbing\", density_kg_per_m3 = 2000.0, "
                  "p_wave_speed_m_per_s = 116.0, s_wave_speed_m_per_s = 62.0 }");
  text = replaced(text, "left = \"roller\"\n", "");
  text = replaced(text, "initial_stress = \"geostatic\"",
                  "initial_stress = \"geostatic\"\nvelocity_x_m_per_s = 0.1");
  text = replaced(text, "kind = \"geostatic\"\nduration_s = 0.5", "duration_s = 0.01");
  text = replaced(text, "local_damping = 0.7\n", "");
  const MpmCase c = read_mpm_case_text(text, "case.toml");
  ASSERT_EQ(phase_settings(c, c.phases[0]).absorbing_boundaries.size(), 1u);
  const std::filesystem::path out = test_support::fresh_temp_path("mpm-absorbing");
  run_mpm_case(c, out, nullptr);
  std::ifstream csv(out / "energies.csv");
  std::string line, last;
  while (std::getline(csv, line))
    if (!line.empty()) last = line;
  const double absorbed = std::stod(last.substr(last.rfind(',') + 1));
  EXPECT_GT(absorbed, 0.0) << last;
  std::filesystem::remove_all(out);
}

TEST(MpmCase, PileRowsOfBodiesCsvAreFullBodyForces) {
  // A pile of one cell's radius, its tip 0.1 m deep, in ground at rest (no surcharge).
  std::string text = replaced(pile_case(), "radius_m = 0.01", "radius_m = 0.05");
  text = replaced(text, "contact_distance_m = 0.01", "contact_distance_m = 0.025");
  text = replaced(text, "normal_kPa = 10.0\nshear_kPa = 1.0", "normal_kPa = 0.0");
  const MpmCase c = read_mpm_case_text(text, "case.toml");
  mpm::Solver solver = make_mpm_solver(c);
  solver.set_settings(phase_settings(c, c.phases[1]));
  MpmPhaseControl install(c, 1, solver);
  install.start(mpm_traction_forces(c, solver.particles()));
  for (int i = 0; i < 30; ++i) {
    const MpmStepPlan plan = install.plan_step(install.end_time(), solver.next_time_step());
    ASSERT_TRUE(plan.own_step);
    solver.step();
  }
  // The ramp: the velocity at the middle of the last step, at most the phase's.
  EXPECT_LT(solver.rigid_body(0).velocity().y(), 0.0);
  EXPECT_GE(solver.rigid_body(0).velocity().y(), -0.1);
  EXPECT_EQ(install.stop_reason(), "");

  const std::string header = mpm_bodies_header(solver);
  EXPECT_NE(header.find("N of the full body"), std::string::npos) << header;
  EXPECT_NE(header.find("force_y_N,force_y_tip_N,force_y_shaft_N,force_y_head_N\n"),
            std::string::npos)
      << header;
  const std::string row = mpm_bodies_rows(solver, {"pile"}, "install");
  std::vector<std::string> fields;
  std::string field;
  std::istringstream cells(row.substr(0, row.size() - 1));
  while (std::getline(cells, field, ',')) fields.push_back(field);
  ASSERT_EQ(fields.size(), 13u) << row;
  EXPECT_EQ(fields[2], "install");
  EXPECT_EQ(fields[3], "pile");
  const mpm::RigidBodyForce& force = solver.rigid_body_force(0);
  EXPECT_GT(force.total.y(), 0.0);       // the ground pushes back
  EXPECT_EQ(std::stod(fields[8]), 0.0);  // the radial forces cancel around the axis
  EXPECT_NEAR(std::stod(fields[9]), 2.0 * kPi * force.total.y(), 1e-8 * force.total.y());
  EXPECT_NEAR(std::stod(fields[10]), 2.0 * kPi * force.parts.at(0).y(), 1e-6 * force.total.y());
  EXPECT_NEAR(std::stod(fields[10]) + std::stod(fields[11]) + std::stod(fields[12]),
              std::stod(fields[9]), 1e-6 * std::stod(fields[9]));
  EXPECT_NEAR(std::stod(fields[5]), solver.rigid_body(0).displacement().y(), 1e-12);
}

}  // namespace
}  // namespace pilempm
