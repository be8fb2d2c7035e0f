#pragma once
// Progress of a run on a stream: on a terminal one line updated in place (the phase, how far it
// is towards its goal, the steps, the wall time and the time left estimated against the phase's
// stop rule), elsewhere (a log file, a pipe) a plain line now and then; and a line at the end
// of each phase.
#include <chrono>
#include <ostream>
#include <string>

#include "pilempm/simulation/run_loop.hpp"

namespace pilempm::simulation {

class ProgressObserver final : public RunObserver {
 public:
  /// `terminal`: `out` is a terminal (lines are updated in place, at most every `interval_s`);
  /// else a plain line every `log_interval_s`. `out` may be nullptr (nothing is written).
  ProgressObserver(std::ostream* out, bool terminal, double interval_s = 0.5,
                   double log_interval_s = 10.0);

  void phase_start(const Scheme& scheme, const MpmPhase& phase) override;
  void after_step(const Scheme& scheme, const MpmPhase& phase, double dt) override;
  void phase_end(const Scheme& scheme, const MpmPhase& phase) override;
  void phase_done(const Scheme& scheme, const MpmPhaseEnd& end) override;
  void failed(const Scheme& scheme, const MpmPhase& phase) override;

  /// Wall time since the observer was made [s].
  double wall_seconds() const;
  /// The progress text of the current phase (what the line shows).
  std::string line(const Scheme& scheme, const MpmPhase& phase) const;

 private:
  void clear_line();

  std::ostream* out_;
  bool terminal_;
  double interval_;
  std::chrono::steady_clock::time_point start_;
  double last_print_ = 0.0;  // wall time of the last line [s]
  double phase_wall_ = 0.0;  // wall time at the phase start [s]
  std::size_t shown_ = 0;    // length of the line shown in place (0: none)
};

}  // namespace pilempm::simulation
