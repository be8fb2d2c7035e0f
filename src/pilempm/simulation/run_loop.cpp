// The run loop over the phases of a case: see run_loop.hpp.
#include "pilempm/simulation/run_loop.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "pilempm/core/error.hpp"

namespace pilempm::simulation {

namespace {

// An output or record interval that the loop could not step through: more times in the phase
// than kMaxSeriesTimes.
void check_interval(const MpmPhase& phase, const char* key, double interval) {
  if (phase.duration / interval <= kMaxSeriesTimes) return;
  throw Error(fmt::format(
      "{} = {:.6g} s gives {:.3g} output times in duration_s = {:.6g} s: must be at least "
      "duration_s / {:.0e} = {:.6g} s",
      key, interval, phase.duration / interval, phase.duration, kMaxSeriesTimes,
      phase.duration / kMaxSeriesTimes));
}

}  // namespace

std::vector<MpmPhaseEnd> run_phases(const MpmCase& c, Scheme& scheme, std::size_t first_phase,
                                    const std::vector<RunObserver*>& observers) {
  auto notify = [&](const auto& call) {
    for (RunObserver* observer : observers) call(*observer);
  };
  // Records and snapshots once per time: the end of a phase is often an output time too.
  double last_record = -1.0, last_snapshot = -1.0;
  auto record = [&](const MpmPhase& phase) {
    if (scheme.time() == last_record) return;
    last_record = scheme.time();
    notify([&](RunObserver& o) { o.record(scheme, phase); });
  };
  auto snapshot = [&](const MpmPhase& phase) {
    if (scheme.time() == last_snapshot) return;
    last_snapshot = scheme.time();
    notify([&](RunObserver& o) { o.snapshot(scheme, phase); });
  };

  notify([&](RunObserver& o) { o.run_start(scheme, first_phase); });
  if (first_phase == 0) {
    record(c.phases.front());
    snapshot(c.phases.front());
  } else {
    // A checkpoint's records end with the rows and the snapshot of its time.
    last_record = last_snapshot = scheme.time();
  }

  std::vector<MpmPhaseEnd> ends;
  for (std::size_t k = first_phase; k < c.phases.size(); ++k) {
    const MpmPhase& phase = c.phases[k];
    MpmPhaseEnd end;
    end.phase = phase.name;
    try {
      end.reason = scheme.begin_phase(k);  // a stop rule met at the start already
      notify([&](RunObserver& o) { o.phase_start(scheme, phase); });
      check_interval(phase, "output_interval_s", phase.output_interval);
      check_interval(phase, "energy_interval_s", phase.energy_interval);
      const double phase_start = scheme.time();
      const double phase_end = scheme.phase_end_time();
      const double tolerance = 1e-6 * std::min(phase.energy_interval, phase.output_interval);
      // The k-th time of a series in this phase (counted, not summed, so that it does not
      // drift); one within the tolerance of the phase end is the phase end.
      auto series_time = [&](double interval, long count) {
        const double t = phase_start + static_cast<double>(count) * interval;
        return t >= phase_end - tolerance ? phase_end : t;
      };
      long output_count = 1, energy_count = 1;
      while (end.reason.empty()) {
        const double next_output = series_time(phase.output_interval, output_count);
        const double next_energy = series_time(phase.energy_interval, energy_count);
        const double target = std::min(next_output, next_energy);
        if (!(target > scheme.time()))
          throw Error(fmt::format(
              "the next output time {:.17g} s is not after the time {:.17g} s: "
              "output_interval_s = {:.6g} s and energy_interval_s = {:.6g} s are below the "
              "resolution of the time",
              target, scheme.time(), phase.output_interval, phase.energy_interval));
        const Advance advance = scheme.advance(target);
        notify([&](RunObserver& o) { o.after_step(scheme, phase, advance.dt); });
        end.reason = advance.stop_reason;
        // A step that ends on the target is at the target whatever the scheme reports: else the
        // same target would come again.
        if (!end.reason.empty() || !(advance.at_target || scheme.time() >= target)) continue;
        // At the target time.
        if (next_energy == target) {
          record(phase);
          ++energy_count;
        }
        if (next_output == target) {
          snapshot(phase);
          ++output_count;
        }
        if (target == phase_end) end.reason = "duration_s";
      }
      record(phase);
      snapshot(phase);
      notify([&](RunObserver& o) { o.phase_end(scheme, phase); });
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      notify([&](RunObserver& o) { o.failed(scheme, phase); });
      throw Error(
          fmt::format("phase \"{}\" at t = {:.6g} s: {}", phase.name, scheme.time(), e.what()));
    }
    if (phase.checkpoint) notify([&](RunObserver& o) { o.checkpoint(scheme, k + 1, phase); });
    end.time = scheme.time();
    end.steps = scheme.steps();
    notify([&](RunObserver& o) { o.phase_done(scheme, end); });
    ends.push_back(std::move(end));
  }
  notify([&](RunObserver& o) { o.run_end(scheme); });
  return ends;
}

}  // namespace pilempm::simulation
