// The length of the explicit step: the CFL condition with the materials' wave speeds.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/explicit/solver.hpp"

namespace pilempm::mpm {

double Solver::next_time_step() {
  if (settings_.fixed_time_step > 0.0) return settings_.fixed_time_step;
  if (wave_speed_step_ < 0 || steps_ - wave_speed_step_ >= settings_.wave_speed_interval) {
    const auto count = static_cast<long>(particles_.size());
    const double mass_scaling = settings_.mass_scaling;
    double max_speed = 0.0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(max : max_speed)
    for (long p = 0; p < count; ++p) {
      const double density = mass_scaling * particles_.mass[p] / particles_.volume[p];
      const double modulus = models_[particles_.material[p]]->wave_modulus(particles_.state[p]);
      max_speed = std::max(max_speed, std::sqrt(modulus / density));
    }
    max_wave_speed_ = max_speed;
    wave_speed_step_ = steps_;
  }
  const double speed = max_wave_speed_ + max_particle_speed_;
  if (!(speed > 0.0 && std::isfinite(speed)))
    throw Error(fmt::format("MPM: no finite wave speed for the time step in step {} ({} m/s)",
                            steps_ + 1, speed));
  double step = settings_.courant_number * grid_.min_spacing() / speed;
  // The penalty springs of the surface contact: at most C 2 / ω_c (solver.hpp).
  if (settings_.contact == ContactScheme::surface && surface_frequency_squared_ > 0.0)
    step = std::min(step, settings_.courant_number * 2.0 / std::sqrt(surface_frequency_squared_));
  return step;
}

}  // namespace pilempm::mpm
