#pragma once
// MPM case texts that several tests run (docs/mpm-case-files.md).

namespace pilempm::test_support {

// A plate pushed into an elastic block under a surcharge, then lifted; the second phase
// switches to a stiffer set.
inline constexpr const char* kPlateIntoBlockCase = R"([geometry]
kind = "plane-strain"
[grid.x]
spacing = "uniform"
min_m = 0.0
max_m = 1.0
cells = 10
[grid.y]
spacing = "uniform"
min_m = 0.0
max_m = 1.0
cells = 10
[boundaries]
left = "roller"
right = "roller"
bottom = "fixed"
[solver]
local_damping = 0.1
threads = 1
[[material]]
name = "soft"
model = "linear-elastic"
young_modulus_MPa = 10.0
poisson_ratio = 0.3
[[material]]
name = "stiff"
model = "linear-elastic"
young_modulus_MPa = 20.0
poisson_ratio = 0.3
[[region]]
name = "block"
x_min_m = 0.0
x_max_m = 1.0
y_min_m = 0.0
y_max_m = 0.5
particles_per_cell = 2
density_kg_per_m3 = 2000.0
material = "soft"
initial_stress = "geostatic"
[[traction]]
region = "block"
side = "top"
normal_kPa = 5.0
[[body]]
name = "plate"
kind = "polygon"
vertices_m = [[0.3, 0.5], [0.7, 0.5], [0.7, 0.6], [0.3, 0.6]]
interface_friction_angle_deg = 20.0
[[phase]]
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
inline const char* const kPileCase = R"([geometry]
kind = "axisymmetric"
[grid.x]
spacing = "uniform"
min_m = 0.0
max_m = 0.4
cells = 8
[grid.y]
spacing = "uniform"
min_m = 0.0
max_m = 0.6
cells = 12
[boundaries]
right = { kind = "absorbing", density_kg_per_m3 = 1600.0, p_wave_speed_m_per_s = 300.0, s_wave_speed_m_per_s = 150.0 }
bottom = "fixed"
[solver]
volumetric_smoothing = true
threads = 1
[[material]]
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
[[material]]
name = "elastic"
model = "linear-elastic"
young_modulus_MPa = 10.0
poisson_ratio = 0.3
[[region]]
name = "ground"
x_min_m = 0.0
x_max_m = 0.4
y_min_m = 0.0
y_max_m = 0.5
particles_per_cell = 2
density_kg_per_m3 = 1600.0
material = "sand"
initial_stress = "geostatic"
[[body]]
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

}  // namespace pilempm::test_support
