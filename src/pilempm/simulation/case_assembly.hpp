#pragma once
// The assembly of a run from a typed case: the grid, the particles with their initial state (the
// geostatic stress included), the rigid bodies and the solver with a phase's settings.
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"
#include "pilempm/mpm/solver.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::simulation {

/// The grid with its boundary conditions (and the axis of symmetry in axisymmetry).
mpm::Grid make_mpm_grid(const MpmCase& mpm_case);
/// The particles of all regions with their initial state (throws InputError at the region when
/// a region cannot be filled or its initial void ratio is impossible).
mpm::Particles make_mpm_particles(const MpmCase& mpm_case, const mpm::Grid& grid);
/// Sets the geostatic state of every particle of a region with initial_stress = "geostatic":
/// σ_v = N g ∫ ρ dy of the regions above it, σ_h = σ_θθ = K0 σ_v, the void ratio from e0 by the
/// region's convention (with the particle's current model), the intergranular strain as at the
/// start, zero velocity. `gravity` is N g [m/s^2].
void set_geostatic_state(const MpmCase& mpm_case, mpm::MpmState& state, double gravity);
/// The solver at time 0, with the [solver] settings, the first phase's gravity and damping, and
/// the rigid bodies (at rest).
mpm::Solver make_mpm_solver(const MpmCase& mpm_case);
/// The solver settings of a phase.
mpm::SolverSettings phase_settings(const MpmCase& mpm_case, const MpmPhase& phase);
/// The quasi-static solver at time 0 with the rigid bodies (at rest): the case's quasi-static
/// settings with the geometry, shape function, gravity and threads of [solver].
mpm::quasi_static::QuasiStaticSolver make_quasi_static_solver(const MpmCase& mpm_case);
/// The quasi-static settings of the case (the same in every phase): [solver]'s quasi-static keys
/// with its geometry, shape function, gravity, threads and volumetric smoothing (B-bar).
mpm::quasi_static::Settings quasi_static_settings(const MpmCase& mpm_case);

}  // namespace pilempm::simulation
