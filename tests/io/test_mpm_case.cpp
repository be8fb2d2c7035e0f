// MPM case files: a valid case reads into SI values; unknown keys and bad values are errors with
// the file, the line, the key, the value and the allowed range.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_output.hpp"

namespace pilempm {
namespace {

// Line numbers below refer to this text (line 1 is `title`).
const char* const kCase = R"(title = "test case"
[geometry]
kind = "axisymmetric"
[grid.x]
spacing = "graded"
min_m = 0.0
max_m = 2.0
band_min_m = 0.0
band_max_m = 0.5
fine_spacing_m = 0.05
growth_ratio = 1.2
[grid.y]
spacing = "uniform"
min_m = -1.0
max_m = 1.0
cells = 20
[boundaries]
left = "roller"
right = "roller"
bottom = "fixed"
[solver]
scheme = "usl"
shape_function = "linear"
flip_fraction = 0.95
gravity_multiplier = 10.0
local_damping = 0.2
courant_number = 0.4
threads = 1
[[material]]
name = "sand"
model = "mohr-coulomb"
young_modulus_MPa = 50.0
poisson_ratio = 0.25
cohesion_kPa = 1.0
friction_angle_deg = 30.0
dilatancy_angle_deg = 0.0
[[region]]
name = "ground"
x_min_m = 0.0
x_max_m = 2.0
y_min_m = -1.0
y_max_m = 0.5
particles_per_cell = [2, 3]
density_kg_per_m3 = 1800.0
material = "sand"
initial_stress = "geostatic"
e0 = 0.7
[[phase]]
name = "equilibrium"
duration_s = 0.5
output_interval_s = 0.1
[[phase]]
name = "load"
duration_s = 2.0
gravity_multiplier = 20.0
local_damping = 0.0
)";

std::string with(const std::string& from, const std::string& to) {
  std::string text = kCase;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  return text;
}

InputError error_of(const std::string& text) {
  try {
    read_mpm_case_text(text, "case.toml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return InputError("", 0, "", "", "");
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
  EXPECT_DOUBLE_EQ(c.solver.courant_number, 0.4);

  ASSERT_EQ(c.regions.size(), 1u);
  const MpmRegion& r = c.regions[0];
  EXPECT_EQ(r.material.kind, ModelKind::mohr_coulomb);
  EXPECT_DOUBLE_EQ(r.material.mohr_coulomb.young_modulus, 50.0e6);  // MPa -> Pa
  EXPECT_DOUBLE_EQ(r.material.mohr_coulomb.cohesion, 1.0e3);        // kPa -> Pa
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
  EXPECT_EQ(region.line(), 44);
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

TEST(MpmCase, MissingPhaseIsAnError) {
  std::string text = kCase;
  text = text.substr(0, text.find("[[phase]]"));
  const InputError e = error_of(text);
  EXPECT_NE(std::string(e.what()).find("[[phase]]"), std::string::npos) << e.what();
}

// A hypoplastic ground with intergranular strain in axisymmetry: e0 given at zero pressure is
// scaled to each particle's geostatic mean stress by Bauer's law, the IGS starts fully mobilised,
// and a short run writes igs_rho and the per-radian energy header.
const char* const kHypoplasticCase = R"(
[geometry]
kind = "axisymmetric"
[grid.x]
spacing = "uniform"
min_m = 0.0
max_m = 0.4
cells = 4
[grid.y]
spacing = "uniform"
min_m = 0.0
max_m = 0.6
cells = 6
[boundaries]
right = "roller"
bottom = "fixed"
[solver]
gravity_multiplier = 50.0
local_damping = 0.5
threads = 1
[[region]]
x_min_m = 0.0
x_max_m = 0.4
y_min_m = 0.0
y_max_m = 0.5
particles_per_cell = 2
density_kg_per_m3 = 1600.0
material = "original"
igs = "IGS1"
initial_stress = "geostatic"
e0 = 0.9
e0_at = "zero-pressure"
[[phase]]
duration_s = 0.002
output_interval_s = 0.001
)";

TEST(MpmCase, HypoplasticGroundStartsAtItsScaledVoidRatioAndRuns) {
  const MpmCase c = read_mpm_case_text(kHypoplasticCase, "hypo.toml");
  const MpmRegion& r = c.regions.at(0);
  EXPECT_EQ(r.material.kind, ModelKind::hypoplastic);
  EXPECT_NEAR(r.K0, 1.0 - std::sin(r.material.hypoplastic.phi_c_deg * kPi / 180.0), 1e-12);
  const mpm::Grid grid = make_mpm_grid(c);
  EXPECT_TRUE(grid.axis_of_symmetry());
  const mpm::Particles particles = make_mpm_particles(c, grid);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const MaterialState& s = particles.state[p];
    const double mean = mean_stress(s.stress);
    EXPECT_NEAR(s.void_ratio,
                initial_void_ratio(r.material.hypoplastic, 0.9,
                                   VoidRatioConvention::at_zero_pressure, mean),
                1e-12);
    EXPECT_LT(s.void_ratio, 0.9);
    EXPECT_GT(s.intergranular_strain.norm(), 0.0);
  }

  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("pilempm-mpm-hypo-" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  const MpmRunSummary summary = run_mpm_case(c, out, nullptr);
  EXPECT_NEAR(summary.time, 0.002, 1e-12);
  ASSERT_EQ(summary.vtu_files.size(), 3u);  // t = 0, 0.001, 0.002
  std::ifstream vtu(summary.vtu_files.back());
  std::ostringstream text;
  text << vtu.rdbuf();
  EXPECT_NE(text.str().find("Name=\"igs_rho\""), std::string::npos);
  std::ifstream csv(summary.energies_file);
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("per radian"), std::string::npos) << header;
  std::filesystem::remove_all(out);
}

TEST(MpmCase, RegionOutsideTheGridIsAnError) {
  const InputError e = error_of(with("y_max_m = 0.5", "y_max_m = 1.5"));
  const std::string message = e.what();
  EXPECT_NE(message.find("region[0].y_max_m = 1.5"), std::string::npos) << message;
  EXPECT_NE(message.find("(-1, 1]"), std::string::npos) << message;
}

}  // namespace
}  // namespace pilempm
