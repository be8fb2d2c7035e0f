// Progress of a run on a stream: see progress.hpp.
#include "pilempm/simulation/progress.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace pilempm::simulation {

ProgressObserver::ProgressObserver(std::ostream* out, bool terminal, double interval_s,
                                   double log_interval_s)
    : out_(out),
      terminal_(terminal),
      interval_(terminal ? interval_s : log_interval_s),
      start_(std::chrono::steady_clock::now()) {}

double ProgressObserver::wall_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string ProgressObserver::line(const Scheme& scheme, const MpmPhase& phase) const {
  const PhaseProgress progress = scheme.phase_progress();
  const double wall = wall_seconds() - phase_wall_;
  // The time left at the pace of the phase so far, towards the goal that ends it first.
  const std::string eta =
      progress.fraction > 0.0
          ? fmt::format("{:.0f} s", wall * (1.0 - progress.fraction) / progress.fraction)
          : std::string("?");
  const std::string report = scheme.step_report();
  return fmt::format(
      "mpm: phase {}: {:.1f} % of {}, t = {:.6g} s, {} steps{}, wall {:.1f} s, ETA {}", phase.name,
      100.0 * progress.fraction, progress.goal, scheme.time(), scheme.steps(),
      report.empty() ? std::string() : " (last: " + report + ")", wall_seconds(), eta);
}

void ProgressObserver::clear_line() {
  if (out_ == nullptr || shown_ == 0) return;
  *out_ << '\r' << std::string(shown_, ' ') << '\r' << std::flush;
  shown_ = 0;
}

void ProgressObserver::phase_start(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {
  phase_wall_ = wall_seconds();
}

void ProgressObserver::after_step(const Scheme& scheme, const MpmPhase& phase, double /*dt*/) {
  if (out_ == nullptr) return;
  const double wall = wall_seconds();
  if (wall - last_print_ < interval_) return;
  last_print_ = wall;
  const std::string text = line(scheme, phase);
  if (!terminal_) {
    *out_ << text << '\n' << std::flush;
    return;
  }
  // In place: back to the line start, the new text, blanks over what is left of the old one.
  *out_ << '\r' << text;
  if (text.size() < shown_) *out_ << std::string(shown_ - text.size(), ' ');
  *out_ << std::flush;
  shown_ = std::max(shown_, text.size());
}

void ProgressObserver::phase_end(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {
  clear_line();  // the phase's own messages (and the end line) start on a clean line
}

void ProgressObserver::failed(const Scheme& /*scheme*/, const MpmPhase& /*phase*/) {
  clear_line();
}

void ProgressObserver::phase_done(const Scheme& /*scheme*/, const MpmPhaseEnd& end) {
  if (out_ == nullptr) return;
  clear_line();
  *out_ << fmt::format("mpm: phase {} ended at t = {:.6g} s, step {}: {}\n", end.phase, end.time,
                       end.steps, end.reason)
        << std::flush;
}

}  // namespace pilempm::simulation
