#pragma once
// Checkpoints of MPM runs in HDF5: everything a run needs to continue exactly as it would have
// without stopping (bitwise, for the same build and thread count): all particle fields with their
// material states, the rigid bodies' positions, velocities and friction, the solver's run state
// (time, step count, energies, cached wave speed, last contact forces), and what the run loop
// needs (the next phase, the particles' initial positions, the output records so far).
// The materials are not stored: a restart takes them from the case file, so a checkpoint can be
// continued with a different parameter set while every particle keeps its stress, void ratio and
// the history variables its model declares (e.g. the intergranular strain). Files are written
// atomically (FILE.<unique>.tmp, then renamed). Every dataset carries a checksum, and HDF5's
// metadata its own: a damaged file is refused naming the dataset. The file layout, the writer and
// the reader are in io/checkpoint/.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "pilempm/mpm/mpm_state.hpp"

namespace pilempm {

/// What the run loop stores in a checkpoint besides the solver.
struct MpmCheckpointInfo {
  std::string case_source;   ///< the case file the run came from (for messages)
  int next_phase = 0;        ///< index of the phase to run next (= phases completed)
  double phase_start = 0.0;  ///< start time of that phase [s] (the time at the checkpoint)
  std::vector<mpm::Vec2> initial_position;  ///< particle positions at t = 0 (displacement output)
  /// Output written so far, by name (for example "energies.csv", "bodies.csv", the PVD entries),
  /// so that a restarted run's files equal the uninterrupted run's.
  std::map<std::string, std::string> records;
  /// Set by read_mpm_checkpoint: the thread count of the solver that wrote the file (ignored by
  /// write). A restart with another count continues to round-off, not bitwise.
  int threads = 0;
};

/// The version of the file layout that write_mpm_checkpoint writes and read_mpm_checkpoint reads.
inline constexpr int kMpmCheckpointFormatVersion = 3;

/// Writes `solver` and `info` to `file` (HDF5), atomically. Throws Error naming the file when
/// it cannot be written.
void write_mpm_checkpoint(const std::filesystem::path& file, const mpm::MpmState& solver,
                          const MpmCheckpointInfo& info);

/// Reads `file` into `solver`, which must be made from the same case (the same geometry, grid
/// node count, number of particles, materials count and rigid bodies with their vertex counts):
/// replaces the particles, the rigid bodies' positions, velocities, friction and contact
/// distances, and the run state. Call it after setting the solver's settings. Throws InputError
/// naming the file and what does not match (nothing in `solver` is changed then).
MpmCheckpointInfo read_mpm_checkpoint(const std::filesystem::path& file, mpm::MpmState& solver);

/// The run information of `file` alone (the next phase, the records; `threads` not set), for a
/// check before a restart changes anything. Throws InputError naming the file when it is not a
/// readable checkpoint of this build's format.
MpmCheckpointInfo read_mpm_checkpoint_info(const std::filesystem::path& file);

}  // namespace pilempm
