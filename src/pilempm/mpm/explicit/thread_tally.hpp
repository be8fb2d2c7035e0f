#pragma once
// What one thread adds up in a stage's particle or node loop, one type per stage, summed
// afterwards in thread order so that the totals do not depend on the order in which the threads
// finish. Each tally fills a cache line of its own (no false sharing between threads).
#include <cstddef>
#include <vector>

#include "pilempm/mpm/particles.hpp"

namespace pilempm::mpm {

inline constexpr std::size_t kNoParticle = static_cast<std::size_t>(-1);

/// The smallest particle index at which a stage failed, and why.
struct ParticleFailure {
  std::size_t particle = kNoParticle;
  const char* reason = "";

  bool any() const { return particle != kNoParticle; }
  void note(std::size_t index, const char* why) {
    if (index < particle) {
      particle = index;
      reason = why;
    }
  }
  void merge(const ParticleFailure& other) { note(other.particle, other.reason); }
};

/// The grid update's sums over a thread's nodes (per radian in axisymmetry).
struct alignas(64) GridUpdateTally {
  double damping_work = 0.0;          ///< energy dissipated by the local damping [J]
  double absorbed_work = 0.0;         ///< energy dissipated by the dashpots [J]
  Vec2 reaction = Vec2::Zero();       ///< force of the boundary constraints on the soil [N]
  Vec2 damping_force = Vec2::Zero();  ///< force of the local damping on the soil [N]
};

/// Grid to particles: the sums over a thread's particles after their move.
struct alignas(64) ParticleMotionTally {
  double external_work = 0.0;      ///< work of gravity and particle loads over the step [J]
  double kinetic_energy = 0.0;     ///< ½ Σ m v² with the inertial mass [J]
  double max_squared_speed = 0.0;  ///< max |v|² [m²/s²]
  ParticleFailure failure;         ///< a particle that left the grid or got no finite velocity
};

/// The stress update's sums over a thread's particles.
struct alignas(64) StressUpdateTally {
  double strain_work = 0.0;  ///< Σ V σ:Δε over the step (trapezoidal rule) [J]
  ParticleFailure failure;   ///< a failed constitutive update
};

/// Zeroes the tallies of a stage before its loop and returns them.
template <class Tally>
std::vector<Tally>& reset_tallies(std::vector<Tally>& tallies) {
  for (Tally& tally : tallies) tally = Tally{};
  return tallies;
}

}  // namespace pilempm::mpm
