#pragma once
// The contact forces on the rigid bodies averaged over time between two records.
#include <vector>

#include "pilempm/mpm/mpm_state.hpp"

namespace pilempm::simulation {

/// The contact forces on the bodies averaged over time between two rows of bodies.csv,
/// Σ F Δt / Σ Δt over the steps: the force of a single step carries the noise of the nodal
/// contact (nodes coming into contact), the mean over an interval is what a load cell shows.
class MpmBodyForceMeans {
 public:
  /// Adds the solver's last step, of length `dt` [s].
  void add_step(const mpm::MpmState& solver, double dt);
  /// The means since the last take() (the last step's forces when no time has passed), and a
  /// new start.
  std::vector<mpm::RigidBodyForce> take(const mpm::MpmState& solver);

 private:
  std::vector<mpm::RigidBodyForce> impulse_;
  double elapsed_ = 0.0;
};

}  // namespace pilempm::simulation
