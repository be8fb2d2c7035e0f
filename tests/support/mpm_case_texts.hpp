#pragma once
// MPM case texts of the tests (docs/mpm-case-files.md): builders of the tables most cases share
// (the grid, the boundaries and the solver's settings, a linear-elastic material, a rectangular
// region), which each test follows with the tables that make it what it is, and the cases that
// several tests run.
#include <array>
#include <charconv>
#include <string>

namespace pilempm::test_support {

/// A number as the case files of the tests write it: the shortest decimal that reads back to it,
/// with a decimal point ("1.0", "0.05", "1600.0").
inline std::string toml_number(double value) {
  std::array<char, 32> buffer{};
  const auto end = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value).ptr;
  std::string text(buffer.data(), end);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}

/// The [boundaries] lines of a box whose sides slide and whose base is fixed.
inline const char* const kRollerSidesFixedBase =
    "left = \"roller\"\nright = \"roller\"\nbottom = \"fixed\"\n";
/// The [boundaries] lines of a container beside the axis (or a plane of symmetry) on the left.
inline const char* const kRollerRightFixedBase = "right = \"roller\"\nbottom = \"fixed\"\n";

/// The opening tables of an MPM case: [geometry], a uniform grid from the origin ([grid.x] and
/// [grid.y]), [boundaries] and [solver], with the lines of the last two as given. By default a
/// plane-strain box 1 m x 1 m of 10 x 10 cells with sliding sides and a fixed base, one thread.
struct MpmCaseOpening {
  std::string geometry = "plane-strain";
  double x_max_m = 1.0;
  int x_cells = 10;
  double y_max_m = 1.0;
  int y_cells = 10;
  std::string boundaries = kRollerSidesFixedBase;
  std::string solver = "threads = 1\n";
};

inline std::string mpm_case_opening(const MpmCaseOpening& o) {
  return "[geometry]\nkind = \"" + o.geometry + "\"\n" +                                      //
         "[grid.x]\nspacing = \"uniform\"\nmin_m = 0.0\nmax_m = " + toml_number(o.x_max_m) +  //
         "\ncells = " + std::to_string(o.x_cells) + "\n" +                                    //
         "[grid.y]\nspacing = \"uniform\"\nmin_m = 0.0\nmax_m = " + toml_number(o.y_max_m) +  //
         "\ncells = " + std::to_string(o.y_cells) + "\n" +                                    //
         "[boundaries]\n" + o.boundaries + "[solver]\n" + o.solver;
}

/// A linear-elastic [[material]] table: E [MPa] and ν.
inline std::string linear_elastic_material_text(const std::string& name, double young_modulus_MPa,
                                                double poisson_ratio = 0.3) {
  return "[[material]]\nname = \"" + name + "\"\nmodel = \"linear-elastic\"\n" +
         "young_modulus_MPa = " + toml_number(young_modulus_MPa) + "\n" +
         "poisson_ratio = " + toml_number(poisson_ratio) + "\n";
}

/// A [[region]] filled with particles: the rectangle [x_min, x_max] x [y_min, y_max] [m], the
/// particles per cell in each direction, density [kg/m^3], material and initial stress; no name
/// line when the name is empty. By default a block 1 m wide and 0.5 m high on the base, 2 x 2
/// particles per cell, 2000 kg/m^3, geostatic. The test adds any further keys of the region after
/// it.
struct MpmRegionText {
  std::string name = "";
  double x_min_m = 0.0;
  double x_max_m = 1.0;
  double y_min_m = 0.0;
  double y_max_m = 0.5;
  int particles_per_cell = 2;
  double density_kg_per_m3 = 2000.0;
  std::string material = "";
  std::string initial_stress = "geostatic";
};

inline std::string mpm_region_text(const MpmRegionText& r) {
  return std::string("[[region]]\n") + (r.name.empty() ? "" : "name = \"" + r.name + "\"\n") +
         "x_min_m = " + toml_number(r.x_min_m) + "\nx_max_m = " + toml_number(r.x_max_m) +
         "\ny_min_m = " + toml_number(r.y_min_m) + "\ny_max_m = " + toml_number(r.y_max_m) +
         "\nparticles_per_cell = " + std::to_string(r.particles_per_cell) +
         "\ndensity_kg_per_m3 = " + toml_number(r.density_kg_per_m3) + "\nmaterial = \"" +
         r.material + "\"\ninitial_stress = \"" + r.initial_stress + "\"\n";
}

/// A rigid plate 0.4 m wide and 0.1 m thick on the middle of the surface of a block 1 m wide and
/// 0.5 m high ([[body]] "plate", interface friction angle 20°).
inline const char* const kPlateBodyText = R"([[body]]
name = "plate"
kind = "polygon"
vertices_m = [[0.3, 0.5], [0.7, 0.5], [0.7, 0.6], [0.3, 0.6]]
interface_friction_angle_deg = 20.0
)";

// A plate pushed into an elastic block under a surcharge, then lifted; the second phase
// switches to a stiffer set.
inline std::string plate_into_block_case() {
  return mpm_case_opening({.solver = "local_damping = 0.1\nthreads = 1\n"}) +
         linear_elastic_material_text("soft", 10.0) + linear_elastic_material_text("stiff", 20.0) +
         mpm_region_text({.name = "block", .material = "soft"}) + R"([[traction]]
region = "block"
side = "top"
normal_kPa = 5.0
)" + kPlateBodyText +
         R"([[phase]]
name = "push"
duration_s = 0.05
output_interval_s = 0.025
energy_interval_s = 0.005
[phase.body.plate]
velocity_y_m_per_s = -0.1
[[phase]]
name = "lift"
duration_s = 0.5
energy_interval_s = 0.005
stop_force_y_below_N = 1000.0
[phase.body.plate]
velocity_y_m_per_s = 0.1
[phase.materials]
soft = "stiff"
)";
}

// An axisymmetric Mohr-Coulomb ground on a graded x axis, with two phases. Tests refer to its
// line numbers (line 1 is `title`).
inline const char* const kMohrCoulombCase = R"(title = "test case"
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
xpic_order = 3
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

// A pile case: rigid body, phase motions, stop rules, material changes, tractions, absorbing
// boundaries and volumetric smoothing.
inline std::string pile_case() {
  return mpm_case_opening({.geometry = "axisymmetric",
                           .x_max_m = 0.4,
                           .x_cells = 8,
                           .y_max_m = 0.6,
                           .y_cells = 12,
                           .boundaries =
                               "right = { kind = \"absorbing\", density_kg_per_m3 = 1600.0, "
                               "p_wave_speed_m_per_s = 300.0, s_wave_speed_m_per_s = 150.0 }\n"
                               "bottom = \"fixed\"\n",
                           .solver = "volumetric_smoothing = true\nthreads = 1\n"}) +
         R"([[material]]
name = "sand"
model = "mohr-coulomb"
young_modulus_MPa = 20.0
poisson_ratio = 0.3
cohesion_kPa = 0.0
friction_angle_deg = 30.0
dilatancy_angle_deg = 0.0
[[material]]
name = "soft-sand"
model = "mohr-coulomb"
young_modulus_MPa = 10.0
poisson_ratio = 0.3
cohesion_kPa = 0.0
friction_angle_deg = 28.0
dilatancy_angle_deg = 0.0
)" + linear_elastic_material_text("elastic", 10.0) +
         mpm_region_text(
             {.name = "ground", .x_max_m = 0.4, .density_kg_per_m3 = 1600.0, .material = "sand"}) +
         R"([[body]]
name = "pile"
kind = "pile"
radius_m = 0.01
tip_y_m = 0.4
tip = "conical"
interface_friction_angle_deg = 20.0
contact_distance_m = 0.01
[[traction]]
region = "ground"
side = "top"
normal_kPa = 10.0
shear_kPa = 1.0
[[phase]]
name = "geostatic"
kind = "geostatic"
duration_s = 0.1
local_damping = 0.5
traction_multiplier = 0.5
[[phase]]
name = "install"
duration_s = 2.0
stop_displacement_y_m = -0.05
checkpoint = false
[phase.body.pile]
velocity_y_m_per_s = -0.1
ramp_s = 0.01
[phase.materials]
sand = "soft-sand"
[[phase]]
name = "relax"
duration_s = 1.0
stop_force_y_below_N = 0.0
stop_phase_displacement_y_m = 0.01
[phase.body.pile]
velocity_y_m_per_s = 0.01
)";
}

}  // namespace pilempm::test_support
