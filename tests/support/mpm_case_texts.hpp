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

}  // namespace pilempm::test_support
