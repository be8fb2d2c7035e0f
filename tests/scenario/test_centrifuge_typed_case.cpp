// The centrifuge scenario builds its MPM case directly; the case file it writes for the record
// (mpm_case.toml), read back, is the same case to the last bit: the same grid, regions, models,
// pile and phases with their roles. So `pilempm mpm run mpm_case.toml` runs what the centrifuge
// run ran.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"

namespace pilempm {
namespace {

using namespace simulation;
using namespace scenario;

// The hypoplastic parameters and the intergranular strain of a model, equal to the bit.
void expect_same_model(const ModelPtr& a, const ModelPtr& b, const std::string& where) {
  const auto* x = dynamic_cast<const Hypoplastic*>(a.get());
  const auto* y = dynamic_cast<const Hypoplastic*>(b.get());
  ASSERT_NE(x, nullptr) << where;
  ASSERT_NE(y, nullptr) << where;
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

void expect_same_case(const MpmCase& typed, const MpmCase& read) {
  EXPECT_EQ(typed.title, read.title);
  EXPECT_EQ(typed.geometry, read.geometry);
  EXPECT_EQ(typed.x_nodes, read.x_nodes);
  EXPECT_EQ(typed.y_nodes, read.y_nodes);
  EXPECT_EQ(typed.boundaries, read.boundaries);
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
  EXPECT_EQ(s.absorbing_boundaries.size(), t.absorbing_boundaries.size());
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
    EXPECT_EQ(a.material.name, b.material.name);
    ASSERT_TRUE(a.igs && b.igs);
    EXPECT_EQ(a.igs->name, b.igs->name);
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
    EXPECT_EQ(a.friction, b.friction);
    EXPECT_EQ(a.contact_distance, b.contact_distance);
  }
  EXPECT_TRUE(typed.tractions.empty() && read.tractions.empty());
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
  const MpmCase read = read_mpm_case_text(centrifuge_mpm_case(s), "mpm_case.toml");
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

}  // namespace
}  // namespace pilempm
