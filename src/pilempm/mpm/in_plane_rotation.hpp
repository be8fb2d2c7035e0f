#pragma once
// The Jaumann rotation of a point's state for a spin about the out-of-plane axis z, the only spin
// in plane strain and axisymmetry. It is the Hughes & Winget (1980) rotation of
// constitutive/objective_rotation.hpp, R = (I - W/2)^-1 (I + W/2), written out for
// W = w (e_y ⊗ e_x - e_x ⊗ e_y): a rotation about z by θ with
//   cos θ = (1 - w²/4) / (1 + w²/4),   sin θ = w / (1 + w²/4),
// applied to the Mandel components directly (about a tenth of the general 3x3 cost; the tests
// check that it equals rotate_state to round-off).
#include <span>

#include "pilempm/constitutive/material_state.hpp"

namespace pilempm::mpm {

/// R A R^T for the rotation about z with cosine c and sine s, on a Mandel vector.
inline void rotate_about_z(Vec6& a, double c, double s) {
  const double cc = c * c, ss = s * s, cs = c * s;
  const double a11 = a[k11], a22 = a[k22], a12 = a[k12], a23 = a[k23], a13 = a[k13];
  a[k11] = cc * a11 + ss * a22 - kSqrt2 * cs * a12;
  a[k22] = ss * a11 + cc * a22 + kSqrt2 * cs * a12;
  a[k12] = kSqrt2 * cs * (a11 - a22) + (cc - ss) * a12;
  a[k13] = c * a13 - s * a23;  // (A13, A23) turns as a vector in the plane
  a[k23] = s * a13 + c * a23;
}

/// The derivative of the turned tensor A = R A₀ Rᵀ with respect to the spin increment w of
/// rotate_state_about_z, given A itself: ∂A/∂θ is the commutator of the rotation's generator
/// with A (in components: ∂A11 = −√2 A12, ∂A22 = √2 A12, ∂A12 = √2 (A11 − A22), ∂A13 = −A23,
/// ∂A23 = A13, Mandel), and θ = 2 atan(w/2), so ∂θ/∂w = 1/(1 + w²/4).
inline Vec6 rotation_derivative_about_z(const Vec6& a, double spin_increment) {
  const double rate = 1.0 / (1.0 + 0.25 * spin_increment * spin_increment);
  Vec6 d = Vec6::Zero();
  d[k11] = -kSqrt2 * a[k12] * rate;
  d[k22] = kSqrt2 * a[k12] * rate;
  d[k12] = kSqrt2 * (a[k11] - a[k22]) * rate;
  d[k13] = -a[k23] * rate;
  d[k23] = a[k13] * rate;
  return d;
}

/// Rotates the stress and the history tensors among `history` (the model's
/// history_variables()) by the spin increment w = W_21 = ½(∂v_y/∂x - ∂v_x/∂y) Δt, the in-plane
/// equivalent of rotate_state().
inline void rotate_state_about_z(MaterialState& state, double spin_increment,
                                 std::span<const HistoryVariable> history) {
  const double quarter_square = 0.25 * spin_increment * spin_increment;
  const double scale = 1.0 / (1.0 + quarter_square);
  const double c = (1.0 - quarter_square) * scale, s = spin_increment * scale;
  rotate_about_z(state.stress, c, s);
  for (const HistoryVariable& v : history) {
    if (!v.tensor) continue;
    double* a = state.history.data() + v.offset;
    // A zero tensor (e.g. the intergranular strain of a model without it) stays zero: skip.
    if (a[k11] == 0.0 && a[k22] == 0.0 && a[k12] == 0.0 && a[k13] == 0.0 && a[k23] == 0.0) continue;
    Vec6 tensor = Eigen::Map<const Vec6>(a);
    rotate_about_z(tensor, c, s);
    Eigen::Map<Vec6> target(a);
    target = tensor;
  }
}

}  // namespace pilempm::mpm
