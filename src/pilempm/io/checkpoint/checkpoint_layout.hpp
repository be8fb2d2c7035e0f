#pragma once
// The layout of the MPM checkpoint file (io/mpm_checkpoint.hpp), shared by its writer and its
// reader so that both see the same fields in the same layout.
//
// File layout (version 2). Doubles are stored as native doubles and integers as native 32/64-bit
// integers, read back without conversion, so a round trip is bitwise.
//   /                  attributes: format, format_version, geometry ("plane-strain" or
//                      "axisymmetric"), grid_nx, grid_ny, particle_count, materials_count,
//                      body_count, threads (of the solver that wrote it, for information),
//                      analysis ("explicit" or "quasi-static": a restart continues the same)
//   /grid              x_nodes, y_nodes (for information; a restart checks the node counts)
//   /particles         one dataset per field, first dimension the particle: position (n, 2),
//                      velocity, mass (n), initial_volume, volume, initial_half_size,
//                      half_size, deformation_gradient (n, 2, 2; [p][row][column]),
//                      out_of_plane_stretch, material (int), external_force, stress (n, 6; Mandel),
//                      void_ratio
//   /particles/history one dataset (n, size) per history variable that a material's model
//                      declares (ConstitutiveModel::history_variables, by name, e.g.
//                      intergranular_strain (n, 6), plastic_shear_strain (n, 1)): a particle's
//                      value where its model declares the variable, zero elsewhere
//   /bodies/<k>        attributes kind ("polygon" or "pile"), part_count, friction,
//                      contact_distance; datasets vertices (m, 2), displacement (2), velocity (2),
//                      contact_force (2), contact_force_parts (parts, 2)
//   /run_state         attributes time, steps, max_wave_speed, wave_speed_step,
//                      max_particle_speed; /run_state/energies attributes kinetic, internal,
//                      external_work, damping, contact_work, absorbed; /run_state/scheme
//                      (the analysis's own arrays, mpm::SolverRunState::scheme_arrays, e.g. the
//                      quasi-static contact points) attribute count, datasets 0, 1, ... of
//                      doubles with attribute name
//   /run               attributes case_source, next_phase, phase_start; dataset initial_position
//                      (0 or n, 2); /run/records attribute count, datasets 0, 1, ...: one
//                      fixed-length string each with attributes name and length (bytes)
// Damage is detected (version 2): every dataset carries an attribute `checksum`, the 64-bit
// FNV-1a hash of its bytes as written, compared with the bytes read; and the file is written in
// HDF5's latest format, whose superblock, object headers (with the attributes) and link
// structures carry HDF5's own checksums, which the library verifies when it reads them.
#include <hdf5.h>

#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "pilempm/mpm/mpm_state.hpp"

namespace pilempm::checkpoint {

inline constexpr const char* kFormat = "pilempm MPM checkpoint";

// The geometry's name as case files spell it.
const char* geometry_name(mpm::Geometry geometry);

// ---------------------------------------------------------------------------------------------
// Per-particle fields: one table for writing and reading, so that both see the same fields in the
// same layout.

struct ParticleField {
  const char* name;
  std::vector<hsize_t> value_dims;
  void (*get)(const mpm::Particles&, std::size_t, double*);
  void (*set)(mpm::Particles&, std::size_t, const double*);
  std::size_t width() const {
    return std::accumulate(value_dims.begin(), value_dims.end(), hsize_t{1},
                           std::multiplies<hsize_t>());
  }
};

// Every double field of the particles (the material index, an int, is stored beside them).
const std::vector<ParticleField>& particle_fields();

// One dataset of /particles/history: a history variable by name, as some model declares it.
struct HistoryDataset {
  std::string name;
  int size;
};

// Every history variable the models declare, once by name (the sizes must agree).
std::vector<HistoryDataset> history_datasets(const std::vector<ModelPtr>& models);

// Where the model keeps the named variable (nullptr: it does not declare it).
const HistoryVariable* find_history(const ConstitutiveModel& model, const std::string& name);

// Points as (x, y) pairs in one array, and back.
std::vector<double> flatten(const std::vector<mpm::Vec2>& points);
std::vector<mpm::Vec2> unflatten(const std::vector<double>& values);

}  // namespace pilempm::checkpoint
