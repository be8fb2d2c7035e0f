#include "pilempm/mpm/surface_contact.hpp"

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm::mpm {

void ContactSettings::validate() const {
  if (!(penalty_factor > 0.0) || !std::isfinite(penalty_factor))
    throw InvalidValue("contact penalty_factor", format_value(penalty_factor), "> 0");
  if (!(tangential_ratio > 0.0) || !std::isfinite(tangential_ratio))
    throw InvalidValue("contact tangential_ratio", format_value(tangential_ratio), "> 0");
  if (!(stiffness_margin >= 0.0) || !std::isfinite(stiffness_margin))
    throw InvalidValue("contact stiffness_margin", format_value(stiffness_margin), ">= 0");
  if (!(smoothing >= 0.0 && smoothing <= 1.0))
    throw InvalidValue("contact smoothing", format_value(smoothing), "in [0, 1]");
  if (!(vertex_radius >= 0.0 && vertex_radius <= 2.0))
    throw InvalidValue("contact vertex_radius", format_value(vertex_radius), "in [0, 2]");
}

PointContact penalty_contact(double gap, const Vec2& normal, const Vec2& slip_increment,
                             const Vec2& previous_tangential_force, double normal_stiffness,
                             double tangential_stiffness, double friction, double margin,
                             double smoothing, double curvature) {
  PointContact contact;
  const Vec2 tangent(-normal.y(), normal.x());
  if (gap >= 0.0 && gap < margin) {
    contact.stiffness = normal_stiffness * normal * normal.transpose() +
                        tangential_stiffness * tangent * tangent.transpose();
    return contact;
  }
  if (!(gap < 0.0)) return contact;
  contact.active = true;
  // f_n(p), p = −g: quadratic up to p = δ, then linear (C¹ at p = 0 and p = δ).
  const double penetration = -gap;
  double normal_slope = normal_stiffness;  // ∂f_n/∂p
  if (penetration < smoothing) {
    normal_slope = normal_stiffness * penetration / smoothing;
    contact.normal_force = 0.5 * normal_slope * penetration;
  } else {
    contact.normal_force = normal_stiffness * (penetration - 0.5 * smoothing);
  }
  const double trial =
      previous_tangential_force.dot(tangent) - tangential_stiffness * slip_increment.dot(tangent);
  const double limit = friction * contact.normal_force;
  contact.stiffness = normal_slope * normal * normal.transpose();
  if (std::abs(trial) <= limit) {
    contact.tangential_force = trial;
    contact.stiffness += tangential_stiffness * tangent * tangent.transpose();
    const Vec2 trial_vector = previous_tangential_force - tangential_stiffness * slip_increment;
    contact.stiffness += curvature * trial_vector.dot(normal) * tangent * tangent.transpose();
  } else {
    contact.slip = true;
    const double sign = trial > 0.0 ? 1.0 : -1.0;
    contact.tangential_force = sign * limit;
    contact.stiffness += sign * friction * normal_slope * tangent * normal.transpose();
  }
  contact.stiffness += curvature *
                       (contact.tangential_force * normal - contact.normal_force * tangent) *
                       tangent.transpose();
  contact.tangential_vector = contact.tangential_force * tangent;
  contact.force = contact.normal_force * normal + contact.tangential_force * tangent;
  return contact;
}

std::vector<double> penalty_moduli(const Particles& particles,
                                   const std::vector<ModelPtr>& models) {
  std::vector<double> modulus(models.size(), 0.0);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const auto m = std::size_t(particles.material[p]);
    modulus[m] = std::max(modulus[m], models[m]->wave_modulus(particles.state[p]));
  }
  return modulus;
}

}  // namespace pilempm::mpm
