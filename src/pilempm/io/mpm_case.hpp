#pragma once
// MPM case files (docs/mpm-case-files.md): the geometry, the background grid and its boundary
// conditions, the solver settings, the materials ([[material]] tables read as in element case
// files), rectangular regions filled with particles and their initial state, and the list of
// phases. Reading is strict: an unknown key or a bad value is an InputError with the file, the
// line, the key, the value and the allowed range. Everything returned is SI.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/io/material_reader.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm {

/// The initial stress of a region.
enum class MpmInitialStress {
  zero,       ///< stress free
  geostatic,  ///< σ_v = N g ∫ ρ dz of the regions above, σ_h = K0 σ_v (N of the first phase)
};

/// One rectangle of particles.
struct MpmRegion {
  std::string name;
  std::string source;       ///< "file:line"
  long line = 0;            ///< the line of its [[region]] header
  std::string key;          ///< "region[i]", for messages
  mpm::RectangleFill fill;  ///< bounds, particles per cell, density; material index set
  MaterialSpec material;
  std::optional<IgsChoice> igs;  ///< hypoplastic only
  bool igs_compression = true;   ///< initial IGS fully mobilised by isotropic compression
  MpmInitialStress initial_stress = MpmInitialStress::zero;
  double K0 = 0.0;  ///< σ_h / σ_v of the geostatic stress [-]
  double e0 = 0.0;  ///< initial void ratio as given [-]
  VoidRatioConvention e0_at = VoidRatioConvention::at_initial_stress;
};

/// One phase of the run: it ends at its start plus its duration.
struct MpmPhase {
  std::string name;
  double duration = 0.0;            ///< [s]
  double gravity_multiplier = 1.0;  ///< N [-]
  double local_damping = 0.0;       ///< α [-]
  double output_interval = 0.0;     ///< between VTU snapshots [s]
  double energy_interval = 0.0;     ///< between rows of energies.csv [s]
};

struct MpmCase {
  std::string source;  ///< the file name used in messages
  std::string title;
  mpm::Geometry geometry = mpm::Geometry::plane_strain;
  std::vector<double> x_nodes, y_nodes;                ///< grid node coordinates [m]
  std::array<mpm::BoundaryCondition, 4> boundaries{};  ///< by mpm::Side
  mpm::SolverSettings solver;               ///< the settings of [solver]; phases override some
  std::vector<std::string> material_names;  ///< index -> name (the regions' materials)
  std::vector<ModelPtr> models;             ///< index -> model
  std::vector<MpmRegion> regions;
  std::vector<MpmPhase> phases;
};

/// Reads a case file (throws InputError).
MpmCase read_mpm_case(const std::filesystem::path& path);
/// Reads case text; `source_name` is what messages call the file.
MpmCase read_mpm_case_text(std::string_view text, const std::string& source_name);

/// The grid with its boundary conditions (and the axis of symmetry in axisymmetry).
mpm::Grid make_mpm_grid(const MpmCase& mpm_case);
/// The particles of all regions with their initial state (throws InputError at the region when
/// a region cannot be filled or its initial void ratio is impossible).
mpm::Particles make_mpm_particles(const MpmCase& mpm_case, const mpm::Grid& grid);
/// The solver at time 0, with the [solver] settings and the first phase's gravity and damping.
mpm::Solver make_mpm_solver(const MpmCase& mpm_case);
/// The solver settings of a phase.
mpm::SolverSettings phase_settings(const MpmCase& mpm_case, const MpmPhase& phase);

}  // namespace pilempm
