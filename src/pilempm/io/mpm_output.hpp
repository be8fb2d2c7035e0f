#pragma once
// Output of MPM runs (docs/mpm-case-files.md, "Output"): a VTU snapshot of the particles per
// output time with a ParaView series (particles.pvd), the energy account as CSV
// (energies.csv), and a progress line on stderr. Files are written atomically.
#include <chrono>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/vtu_writer.hpp"
#include "pilempm/mpm/solver.hpp"

namespace pilempm {

/// The particles as a point cloud, with the fields listed in docs/mpm-case-files.md.
/// `initial_position` gives the displacement; `material_index` maps a model index to the index
/// of its material name (what the "material" field holds).
PointCloud mpm_particle_cloud(const mpm::Solver& solver,
                              const std::vector<mpm::Vec2>& initial_position,
                              const std::vector<int>& material_index);

/// The header of energies.csv (a comment line with the units, then the column names).
std::string mpm_energies_header(mpm::Geometry geometry);
/// One row of energies.csv; `time_step` is the step the solver takes from there (CFL) [s].
std::string mpm_energies_row(const mpm::Solver& solver, double time_step);

/// A progress line on a stream, at most one per `min_interval` of wall time.
class MpmProgress {
 public:
  MpmProgress(std::ostream* out, double total_time, double min_interval_s = 0.5);
  /// Prints when the last line is older than the interval (or always when `force`).
  void update(const std::string& phase, double phase_end, const mpm::Solver& solver,
              bool force = false);
  double wall_seconds() const;

 private:
  std::ostream* out_;
  double total_time_;
  double min_interval_;
  std::chrono::steady_clock::time_point start_;
  double last_print_ = 0.0;  // the first line after one interval
};

/// What a run did.
struct MpmRunSummary {
  long steps = 0;
  double time = 0.0;
  double wall_seconds = 0.0;
  std::vector<std::filesystem::path> vtu_files;
  std::filesystem::path pvd_file, energies_file;
};

/// Runs the phases of a case, writing into `out_dir` (created if needed): particles_NNNNN.vtu,
/// particles.pvd, energies.csv. Progress lines go to `progress` (nullptr: none). Throws Error
/// naming the phase when the solver fails; what was written up to then stays valid.
MpmRunSummary run_mpm_case(const MpmCase& mpm_case, const std::filesystem::path& out_dir,
                           std::ostream* progress);

}  // namespace pilempm
