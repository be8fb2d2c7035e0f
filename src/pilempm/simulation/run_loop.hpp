#pragma once
// The run loop over the phases of a case (docs/mpm-case-files.md, "Phases" and "Output"),
// whatever the scheme: each phase is begun, then advanced to its next output time (VTU
// snapshot), record time (rows of energies.csv and bodies.csv) or end, until its duration is
// over or a stop rule is met. The loop decides when; observers write, record and report.
#include <cstddef>
#include <string>
#include <vector>

#include "pilempm/simulation/mpm_case.hpp"
#include "pilempm/simulation/scheme.hpp"

namespace pilempm::simulation {

/// How a phase of a run ended.
struct MpmPhaseEnd {
  std::string phase;
  double time = 0.0;   ///< [s]
  long steps = 0;      ///< the step count then
  std::string reason;  ///< "duration_s" or the stop rule met, with the value reached
};

/// What the loop tells the observers of a run, in this order for each phase: phase_start,
/// after_step after every step, record and snapshot at their times (once per time), then
/// record and snapshot at the phase end, phase_end, checkpoint (when the phase asks for one) and
/// phase_done. `failed` is called when the scheme throws (before the error goes on).
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// Before the first phase of this run (`first_phase` > 0 on a restart).
  virtual void run_start(const Scheme& /*scheme*/, std::size_t /*first_phase*/) {}
  virtual void phase_start(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {}
  /// After every step; `dt` its length [s].
  virtual void after_step(const Scheme& /*scheme*/, const MpmPhase& /*phase*/, double /*dt*/) {}
  /// A record time: the rows of energies and bodies.
  virtual void record(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {}
  /// An output time: a snapshot of the particles.
  virtual void snapshot(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {}
  /// At the phase end, after its last record and snapshot, before its checkpoint.
  virtual void phase_end(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {}
  /// The phase asks for a checkpoint; `phases_done` counts the phases completed.
  virtual void checkpoint(const Scheme& /*scheme*/, std::size_t /*phases_done*/,
                          const MpmPhase& /*phase*/) {}
  /// The phase is over (after its checkpoint).
  virtual void phase_done(const Scheme& /*scheme*/, const MpmPhaseEnd& /*end*/) {}
  /// The scheme failed in `phase`; the error is thrown on after this.
  virtual void failed(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {}
  /// After the last phase.
  virtual void run_end(const Scheme& /*scheme*/) {}
};

/// The most output or record times one phase may have: a smaller interval is an error, not a
/// loop that could not end.
inline constexpr double kMaxSeriesTimes = 1e8;

/// Runs the phases of `mpm_case` from `first_phase` on (> 0: a restart, the scheme's state read
/// from a checkpoint) with `scheme`, telling `observers` (in their order). On a fresh run the
/// start is recorded and snapshot first. Throws Error naming the phase and time when the scheme
/// fails, or when an output_interval_s or energy_interval_s is too small for the loop to advance
/// (more than kMaxSeriesTimes times in the phase, or below the resolution of the time).
std::vector<MpmPhaseEnd> run_phases(const MpmCase& mpm_case, Scheme& scheme,
                                    std::size_t first_phase,
                                    const std::vector<RunObserver*>& observers);

}  // namespace pilempm::simulation
