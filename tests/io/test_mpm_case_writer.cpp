// The MPM case writer (io/mpm_case_writer.hpp): a typed case written as a case file and read
// back is the same case to the last bit, field by field. The centrifuge scenario builds its MPM
// case directly, and the file it writes for the record (mpm_case.toml) is read back as that case:
// the same grid, regions, models, pile and phases with their roles, so `pilempm mpm run
// mpm_case.toml` runs what the centrifuge run ran. Every example MPM case, read, written and read
// again, is the case first read.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "../support/input_texts.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_case_writer.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"

namespace pilempm {
namespace {

using namespace simulation;
using namespace scenario;

// The hypoplastic parameters and the intergranular strain of two models, equal to the bit.
void expect_same_hypoplastic(const Hypoplastic* x, const Hypoplastic* y, const std::string& where) {
  const HypoplasticParameters &p = x->parameters(), &q = y->parameters();
  EXPECT_EQ(p.phi_c_deg, q.phi_c_deg) << where;
  EXPECT_EQ(p.h_s, q.h_s) << where;
  EXPECT_EQ(p.n, q.n) << where;
  EXPECT_EQ(p.e_d0, q.e_d0) << where;
  EXPECT_EQ(p.e_c0, q.e_c0) << where;
  EXPECT_EQ(p.e_i0, q.e_i0) << where;
  EXPECT_EQ(p.alpha, q.alpha) << where;
  EXPECT_EQ(p.beta, q.beta) << where;
  const IntergranularStrainParameters &i = x->intergranular(), &j = y->intergranular();
  EXPECT_EQ(i.R, j.R) << where;
  EXPECT_EQ(i.m_R, j.m_R) << where;
  EXPECT_EQ(i.m_T, j.m_T) << where;
  EXPECT_EQ(i.beta_r, j.beta_r) << where;
  EXPECT_EQ(i.chi, j.chi) << where;
}

// A model's parameters as text, through its registration's description (every parameter, the
// intergranular strain and the integrator settings of the models that use them).
class DescriptionSink final : public ParameterSink {
 public:
  void number(std::string_view key, double value) override { add(key, fmt::format("{}", value)); }
  void integer(std::string_view key, long value) override { add(key, std::to_string(value)); }
  void text(std::string_view key, std::string_view value) override { add(key, value); }
  void boolean(std::string_view key, bool value) override { add(key, value ? "true" : "false"); }
  void begin_group(std::string_view key) override { text_ += std::string(key) + " { "; }
  void end_group() override { text_ += "} "; }
  std::string text_;

 private:
  void add(std::string_view key, std::string_view value) {
    text_ += fmt::format("{} = {}; ", key, value);
  }
};

std::string description(const MaterialSpec& m, const IntegratorSettings& integrator) {
  DescriptionSink sink;
  model_registry().at(m.model).describe(*m.parameters, integrator, sink);
  return fmt::format("{} ({}, builtin {}, note \"{}\"): {}", m.name, m.model, m.builtin, m.note,
                     sink.text_);
}

// Two models answer one strain increment from one state with the same stress and void ratio,
// to the bit; hypoplastic ones have the same parameters and intergranular strain, to the bit.
void expect_same_model(const ModelPtr& a, const ModelPtr& b, const std::string& where) {
  ASSERT_NE(a, nullptr) << where;
  ASSERT_NE(b, nullptr) << where;
  EXPECT_EQ(a->name(), b->name()) << where;
  MaterialState from;
  from.stress = Vec6::Zero();
  from.stress.head<3>().setConstant(-100.0e3);  // 100 kPa all round (tension positive)
  from.void_ratio = 0.7;
  Vec6 increment = Vec6::Zero();
  increment[1] = -1.0e-4;  // vertical compression
  increment[0] = 0.3e-4;
  MaterialState x = from, y = from;
  (void)a->update(x, increment);
  (void)b->update(y, increment);
  EXPECT_EQ(x.stress, y.stress) << where;
  EXPECT_EQ(x.void_ratio, y.void_ratio) << where;
  const auto* h = dynamic_cast<const Hypoplastic*>(a.get());
  const auto* k = dynamic_cast<const Hypoplastic*>(b.get());
  ASSERT_EQ(h == nullptr, k == nullptr) << where;
  if (h != nullptr) expect_same_hypoplastic(h, k, where);
}

void expect_same_axis(const MpmGridAxis& a, const MpmGridAxis& b) {
  EXPECT_EQ(a.graded, b.graded);
  EXPECT_EQ(a.min, b.min);
  EXPECT_EQ(a.max, b.max);
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.band_min, b.band_min);
  EXPECT_EQ(a.band_max, b.band_max);
  EXPECT_EQ(a.fine_spacing, b.fine_spacing);
  EXPECT_EQ(a.growth_ratio, b.growth_ratio);
  EXPECT_EQ(a.max_spacing, b.max_spacing);
}

// Every field of the two cases but where they came from (source, lines, keys), to the bit.
void expect_same_case(const MpmCase& typed, const MpmCase& read) {
  EXPECT_EQ(typed.title, read.title);
  EXPECT_EQ(typed.geometry, read.geometry);
  expect_same_axis(typed.x_axis, read.x_axis);
  expect_same_axis(typed.y_axis, read.y_axis);
  EXPECT_EQ(typed.x_nodes, read.x_nodes);
  EXPECT_EQ(typed.y_nodes, read.y_nodes);
  EXPECT_EQ(typed.boundaries, read.boundaries);
  EXPECT_EQ(typed.analysis, read.analysis);
  EXPECT_EQ(typed.displacement_step, read.displacement_step);
  const mpm::quasi_static::Settings &q = typed.quasi_static, &u = read.quasi_static;
  EXPECT_EQ(q.force_tolerance, u.force_tolerance);
  EXPECT_EQ(q.energy_tolerance, u.energy_tolerance);
  EXPECT_EQ(q.max_iterations, u.max_iterations);
  EXPECT_EQ(q.max_cuts, u.max_cuts);
  EXPECT_EQ(q.accept_tolerance, u.accept_tolerance);
  EXPECT_EQ(q.stall_iterations, u.stall_iterations);
  EXPECT_EQ(q.tangent_reuse, u.tangent_reuse);
  EXPECT_EQ(q.midpoint_strain, u.midpoint_strain);
  EXPECT_EQ(q.linear_solver, u.linear_solver);
  EXPECT_EQ(q.contact.penalty_factor, u.contact.penalty_factor);
  const mpm::SolverSettings &s = typed.solver, &t = read.solver;
  EXPECT_EQ(s.geometry, t.geometry);
  EXPECT_EQ(s.scheme, t.scheme);
  EXPECT_EQ(s.shape_function, t.shape_function);
  EXPECT_EQ(s.flip_fraction, t.flip_fraction);
  EXPECT_EQ(s.xpic_order, t.xpic_order);
  EXPECT_EQ(s.gravity, t.gravity);
  EXPECT_EQ(s.gravity_multiplier, t.gravity_multiplier);
  EXPECT_EQ(s.local_damping, t.local_damping);
  EXPECT_EQ(s.mass_scaling, t.mass_scaling);
  EXPECT_EQ(s.courant_number, t.courant_number);
  EXPECT_EQ(s.fixed_time_step, t.fixed_time_step);
  EXPECT_EQ(s.threads, t.threads);
  EXPECT_EQ(s.volumetric_smoothing, t.volumetric_smoothing);
  EXPECT_EQ(s.contact, t.contact);
  ASSERT_EQ(s.absorbing_boundaries.size(), t.absorbing_boundaries.size());
  for (std::size_t k = 0; k < s.absorbing_boundaries.size(); ++k) {
    const mpm::AbsorbingBoundary &a = s.absorbing_boundaries[k], &b = t.absorbing_boundaries[k];
    EXPECT_EQ(a.side, b.side);
    EXPECT_EQ(a.density, b.density);
    EXPECT_EQ(a.p_wave_speed, b.p_wave_speed);
    EXPECT_EQ(a.s_wave_speed, b.s_wave_speed);
  }
  const IntegratorSettings &i = typed.integrator, &j = read.integrator;
  EXPECT_EQ(i.scheme, j.scheme);
  EXPECT_EQ(i.tolerance, j.tolerance);
  EXPECT_EQ(i.fixed_substeps, j.fixed_substeps);
  EXPECT_EQ(i.max_substeps, j.max_substeps);
  EXPECT_EQ(i.min_substep, j.min_substep);
  EXPECT_EQ(i.min_mean_stress, j.min_mean_stress);
  ASSERT_EQ(typed.materials.size(), read.materials.size());
  for (std::size_t m = 0; m < typed.materials.size(); ++m)
    EXPECT_EQ(description(typed.materials[m], i), description(read.materials[m], j));
  EXPECT_EQ(typed.material_names, read.material_names);
  ASSERT_EQ(typed.models.size(), read.models.size());
  for (std::size_t m = 0; m < typed.models.size(); ++m)
    expect_same_model(typed.models[m], read.models[m], "model " + std::to_string(m));

  ASSERT_EQ(typed.regions.size(), read.regions.size());
  for (std::size_t k = 0; k < typed.regions.size(); ++k) {
    const MpmRegion &a = typed.regions[k], &b = read.regions[k];
    SCOPED_TRACE(a.name);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.fill.x_min, b.fill.x_min);
    EXPECT_EQ(a.fill.x_max, b.fill.x_max);
    EXPECT_EQ(a.fill.y_min, b.fill.y_min);
    EXPECT_EQ(a.fill.y_max, b.fill.y_max);
    EXPECT_EQ(a.fill.particles_per_cell_x, b.fill.particles_per_cell_x);
    EXPECT_EQ(a.fill.particles_per_cell_y, b.fill.particles_per_cell_y);
    EXPECT_EQ(a.fill.density, b.fill.density);
    EXPECT_EQ(a.fill.initial_velocity, b.fill.initial_velocity);
    EXPECT_EQ(a.fill.material, b.fill.material);
    EXPECT_EQ(description(a.material, i), description(b.material, j));
    ASSERT_EQ(a.igs.has_value(), b.igs.has_value());
    if (a.igs) {
      EXPECT_EQ(a.igs->name, b.igs->name);
      const IntergranularStrainParameters &g = a.igs->parameters, &h = b.igs->parameters;
      EXPECT_EQ(g.R, h.R);
      EXPECT_EQ(g.m_R, h.m_R);
      EXPECT_EQ(g.m_T, h.m_T);
      EXPECT_EQ(g.beta_r, h.beta_r);
      EXPECT_EQ(g.chi, h.chi);
    }
    EXPECT_EQ(a.igs_in_region, b.igs_in_region);
    EXPECT_EQ(a.igs_compression, b.igs_compression);
    EXPECT_EQ(a.initial_stress, b.initial_stress);
    EXPECT_EQ(a.K0, b.K0);
    EXPECT_EQ(a.e0, b.e0);
    EXPECT_EQ(a.e0_at, b.e0_at);
  }
  ASSERT_EQ(typed.bodies.size(), read.bodies.size());
  for (std::size_t k = 0; k < typed.bodies.size(); ++k) {
    const MpmBody &a = typed.bodies[k], &b = read.bodies[k];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.radius, b.radius);
    EXPECT_EQ(a.tip_y, b.tip_y);
    EXPECT_EQ(a.apex_angle, b.apex_angle);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.friction, b.friction);
    EXPECT_EQ(a.contact_distance, b.contact_distance);
  }
  ASSERT_EQ(typed.tractions.size(), read.tractions.size());
  for (std::size_t k = 0; k < typed.tractions.size(); ++k) {
    const MpmTraction &a = typed.tractions[k], &b = read.tractions[k];
    EXPECT_EQ(a.region, b.region);
    EXPECT_EQ(a.side, b.side);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.shear, b.shear);
  }
  ASSERT_EQ(typed.phases.size(), read.phases.size());
  for (std::size_t k = 0; k < typed.phases.size(); ++k) {
    const MpmPhase &a = typed.phases[k], &b = read.phases[k];
    SCOPED_TRACE(a.name);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.role, b.role);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.duration, b.duration);
    EXPECT_EQ(a.gravity_multiplier, b.gravity_multiplier);
    EXPECT_EQ(a.local_damping, b.local_damping);
    EXPECT_EQ(a.output_interval, b.output_interval);
    EXPECT_EQ(a.energy_interval, b.energy_interval);
    EXPECT_EQ(a.traction_multiplier, b.traction_multiplier);
    EXPECT_EQ(a.displacement_step, b.displacement_step);
    EXPECT_EQ(a.checkpoint, b.checkpoint);
    ASSERT_EQ(a.body_motion.size(), b.body_motion.size());
    for (std::size_t m = 0; m < a.body_motion.size(); ++m) {
      EXPECT_EQ(a.body_motion[m].velocity, b.body_motion[m].velocity);
      EXPECT_EQ(a.body_motion[m].ramp, b.body_motion[m].ramp);
    }
    EXPECT_EQ(a.stop_body, b.stop_body);
    ASSERT_EQ(a.stop_rules.size(), b.stop_rules.size());
    for (std::size_t r = 0; r < a.stop_rules.size(); ++r) {
      EXPECT_EQ(a.stop_rules[r].key, b.stop_rules[r].key);
      EXPECT_EQ(a.stop_rules[r].quantity, b.stop_rules[r].quantity);
      EXPECT_EQ(a.stop_rules[r].component, b.stop_rules[r].component);
      EXPECT_EQ(a.stop_rules[r].value, b.stop_rules[r].value);
    }
    EXPECT_EQ(a.stop_force_averaging, b.stop_force_averaging);
    ASSERT_EQ(a.material_changes.size(), b.material_changes.size());
    for (std::size_t m = 0; m < a.material_changes.size(); ++m) {
      EXPECT_EQ(a.material_changes[m].model, b.material_changes[m].model);
      EXPECT_EQ(a.material_changes[m].material, b.material_changes[m].material);
      expect_same_model(a.material_changes[m].replacement, b.material_changes[m].replacement,
                        "material change");
    }
  }
}

void expect_written_case_is_the_typed_case(const std::string& text) {
  const CentrifugeScenario s = read_centrifuge_case_text(text, "centrifuge.toml");
  const MpmCase typed = centrifuge_case(s, "mpm_case.toml");
  const MpmCase read = read_mpm_case_text(centrifuge_mpm_case_text(typed), "mpm_case.toml");
  for (const MpmRegion& r : typed.regions) ASSERT_TRUE(r.igs && r.igs->parameters.enabled());
  EXPECT_TRUE(typed.tractions.empty());
  expect_same_case(typed, read);
}

TEST(CentrifugeTypedCase, TheQuickCaseFileReadBackIsTheTypedCase) {
  expect_written_case_is_the_typed_case(
      read_case_text(std::string(PILEMPM_SOURCE_DIR) + "/examples/centrifuge/quick.toml"));
}

// Every optional part: an own material, a load-test set, split installation, one region, a
// flat tip, relaxation, an odd pile diameter and g-level whose numbers need all 9 digits.
TEST(CentrifugeTypedCase, ACaseWithEveryPartReadBackIsTheTypedCase) {
  expect_written_case_is_the_typed_case(R"(title = "every part"
[[material]]
name = "steep-sand"
model = "hypoplastic"
base = "original"
phi_c_deg = 33.3
[test]
pile_diameter_mm = 11.7
g_level = 43.7
container_radius_D = 7.3
sand_height_D = 13.1
[sand]
material = "steep-sand"
load_test_material = "modified-medium-dense"
igs = "IGS2"
e0 = 0.713
e0_at = "zero-pressure"
[pile]
tip = "flat"
[installation]
wished_in_place_D = 2.7
depth_D = 1.9
velocity_m_per_s = 0.031
snapshot_depths_D = [3.3, 4.1]
[load_test]
displacement_D = 0.13
[mesh]
cells_per_D = 3
particles_per_cell = 2
particles_per_cell_outside = 2
)");
}

// A case read from a file, written and read again: the same case; written again: the same text.
void expect_round_trip(const MpmCase& first) {
  const std::string text = mpm_case_text(first);
  const MpmCase second = read_mpm_case_text(text, "written.toml");
  expect_same_case(first, second);
  EXPECT_EQ(mpm_case_text(second), text);
}

TEST(MpmCaseWriter, EveryExampleMpmCaseReadWrittenAndReadAgainIsTheSameCase) {
  namespace fs = std::filesystem;
  int cases = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(PILEMPM_SOURCE_DIR) / "examples/mpm")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().filename().string());
    expect_round_trip(read_mpm_case(entry.path()));
    ++cases;
  }
  EXPECT_GE(cases, 20);
}

// The case files of the tests, which hold every key of the reader between them: graded and
// uniform axes, absorbing sides, tractions, a pile, stop rules on displacement and force, material
// changes, [n_x, n_y] particles per cell.
TEST(MpmCaseWriter, TheTestCasesWithEveryKeyReadWrittenAndReadAgainAreTheSameCase) {
  expect_round_trip(read_mpm_case_text(test_support::kMohrCoulombCase, "case.toml"));
  expect_round_trip(read_mpm_case_text(test_support::pile_case(), "pile.toml"));
  const std::string surface =
      test_support::replaced(test_support::kMohrCoulombCase, "local_damping = 0.2",
                             "local_damping = 0.2\ncontact = \"surface\"");
  const MpmCase with_surface = read_mpm_case_text(surface, "case.toml");
  ASSERT_EQ(with_surface.solver.contact, mpm::ContactScheme::surface);
  expect_round_trip(with_surface);
}

// A polygon with a friction angle and an apex angle whose radians need every digit, an
// [integrator] table, an inline intergranular strain on a base set, a hypoplastic [[material]]
// with a stress dependence, initial velocities and a zero initial intergranular strain.
TEST(MpmCaseWriter, AHypoplasticCaseWithOwnTablesReadWrittenAndReadAgainIsTheSameCase) {
  expect_round_trip(read_mpm_case_text(R"(title = "every hypoplastic key"
[geometry]
kind = "plane-strain"
[grid.x]
spacing = "uniform"
min_m = -0.3
max_m = 0.3
cells = 12
[grid.y]
spacing = "graded"
min_m = 0.0
max_m = 0.5
band_min_m = 0.3
band_max_m = 0.5
fine_spacing_m = 0.0123
growth_ratio = 1.17
max_spacing_m = 0.09
[integrator]
scheme = "bogacki-shampine"
tolerance = 3.3e-4
fixed_substeps = 0
[[material]]
name = "stiff-sand"
model = "hypoplastic"
note = "a test set"
base = "original"
h_s_MPa = 1234.567
igs = "IGS2"
stress_dependence = { alpha = true, p_low_kPa = 123.4, p_high_kPa = 5678.9 }
[[region]]
name = "sand"
x_min_m = -0.3
x_max_m = 0.3
y_min_m = 0.0
y_max_m = 0.4
particles_per_cell = [3, 2]
density_kg_per_m3 = 1611.3
velocity_x_m_per_s = 0.01
material = "stiff-sand"
igs = { base = "IGS3", R = 2.3e-4 }
igs_initial = "zero"
initial_stress = "geostatic"
K0 = 0.47
e0 = 0.71
e0_at = "zero-pressure"
[[body]]
name = "footing"
kind = "polygon"
vertices_m = [[-0.05, 0.41], [0.05, 0.41], [0.05, 0.47], [-0.05, 0.47]]
interface_friction_angle_deg = 23.3
[[phase]]
name = "settle"
kind = "geostatic"
role = "initial-stress"
duration_s = 0.05
local_damping = 0.3
energy_interval_s = 0.001
[[phase]]
name = "push"
duration_s = 0.2
stop_force_y_above_N = 5000.0
stop_force_averaging_s = 0.002
stop_displacement_y_m = -0.01
[phase.body.footing]
velocity_y_m_per_s = -0.05
ramp_s = 0.01
[phase.materials]
stiff-sand = "modified-medium-dense"
)",
                                       "hypoplastic.toml"));
}

// TOML strings: the title's quote, backslash and tab are escaped.
TEST(MpmCaseWriter, TitleAndMaterialNamesAreWrittenAsTomlStrings) {
  CentrifugeScenario s;
  s.title = "a \"quoted\" title with a back\\slash and a\ttab";
  const MpmCase typed = centrifuge_case(s, "mpm_case.toml");
  const std::string text = centrifuge_mpm_case_text(typed);
  EXPECT_NE(text.find(R"(title = "a \"quoted\" title with a back\\slash and a\u0009tab")"),
            std::string::npos)
      << text.substr(0, 200);
  EXPECT_EQ(read_mpm_case_text(text, "mpm_case.toml").title, s.title);
}

// A case that cannot be a file is refused, naming why.
TEST(MpmCaseWriter, NodesThatAreNotThoseOfTheAxisAreRefused) {
  MpmCase c = read_mpm_case_text(test_support::kMohrCoulombCase, "case.toml");
  c.x_nodes.back() += 1.0e-3;
  try {
    (void)mpm_case_text(c);
    ADD_FAILURE() << "written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x nodes"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pilempm
