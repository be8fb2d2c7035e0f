// Contact forces averaged over time: see body_force_means.hpp.
#include "pilempm/simulation/body_force_means.hpp"

namespace pilempm::simulation {

void MpmBodyForceMeans::add_step(const mpm::MpmState& solver, double dt) {
  impulse_.resize(static_cast<std::size_t>(solver.rigid_body_count()));
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const mpm::RigidBodyForce& force = solver.rigid_body_force(b);
    mpm::RigidBodyForce& sum = impulse_[static_cast<std::size_t>(b)];
    sum.parts.resize(force.parts.size(), mpm::Vec2::Zero());
    sum.total += dt * force.total;
    for (std::size_t k = 0; k < force.parts.size(); ++k) sum.parts[k] += dt * force.parts[k];
  }
  elapsed_ += dt;
}

std::vector<mpm::RigidBodyForce> MpmBodyForceMeans::take(const mpm::MpmState& solver) {
  std::vector<mpm::RigidBodyForce> means;
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    if (elapsed_ > 0.0 && static_cast<std::size_t>(b) < impulse_.size()) {
      mpm::RigidBodyForce mean = impulse_[static_cast<std::size_t>(b)];
      mean.total /= elapsed_;
      for (mpm::Vec2& part : mean.parts) part /= elapsed_;
      means.push_back(std::move(mean));
    } else {
      means.push_back(solver.rigid_body_force(b));
    }
  }
  impulse_.clear();
  elapsed_ = 0.0;
  return means;
}

}  // namespace pilempm::simulation
