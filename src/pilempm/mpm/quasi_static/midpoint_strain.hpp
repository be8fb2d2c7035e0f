#pragma once
// The strain and spin increments of a load step on the increment's midpoint configuration, as
// Hughes & Winget (1980, Int. J. Numer. Meth. Eng. 15, 1862-1867) define them: with
// G = ∂Δu/∂x_n the displacement increment's gradient on the start configuration,
//   L = ∂Δu/∂x_{n+1/2} = G (I + G/2)⁻¹,   Δε = sym L,   w = ½ (L_yx − L_xy),
// and in axisymmetry the hoop increment Δu_r / r_{n+1/2} = h / (1 + h/2), h = Δu_r / r_n.
// Summed over load steps these are second-order approximations of the logarithmic strain (a
// rigid rotation gives Δε = 0, a uniaxial stretch λ gives 2(λ − 1)/(λ + 1) for ln λ); sym G,
// taken on the start configuration, is first-order (a rotation by θ gives the spurious normal
// strain cos θ − 1 ≈ −θ²/2 in each in-plane direction).
//
// In 2-D the Cayley-Hamilton theorem gives the map in closed form:
//   L = (G + ½ det G · I) / m,   m = det(I + G/2) = 1 + ½ tr G + ¼ det G.
// The map and its derivative are written in the linear (start configuration) increments
// e = (G_xx, G_yy, h, (G_xy + G_yx)/√2, ½ (G_yx − G_xy)): the strain's Mandel components
// 11, 22, 33, 12 and the spin, which is what the Newton matrix's rows hold.
#include <Eigen/Dense>
#include <cmath>

namespace pilempm::mpm::quasi_static::detail {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

/// det G of the linear increments `e`: G_xx G_yy − G_xy G_yx, with G_xy G_yx = e12²/2 − w².
inline double gradient_determinant(const Vec5& e) {
  return e[0] * e[1] - 0.5 * e[3] * e[3] + e[4] * e[4];
}

/// det(I + G/2) = 1 + ½ tr G + ¼ det G, given det G.
inline double midpoint_determinant(const Vec5& e, double det) {
  return 1.0 + 0.5 * (e[0] + e[1]) + 0.25 * det;
}

/// Whether the midpoint configuration of the linear increments `e` exists: det(I + G/2) > 0
/// and 1 + h/2 > 0 (an increment that turns the particle inside out has none).
inline bool has_midpoint(const Vec5& e) {
  return midpoint_determinant(e, gradient_determinant(e)) > 0.0 && 1.0 + 0.5 * e[2] > 0.0;
}

/// The midpoint increments (Δε_11, Δε_22, Δε_33, √2 Δε_12, w) of the linear ones `e` (above),
/// and, when `jacobian` is given, their derivative with respect to `e`.
inline Vec5 midpoint_increments(const Vec5& e, Mat5* jacobian = nullptr) {
  const double e11 = e[0], e22 = e[1], h = e[2], e12 = e[3], w = e[4];
  const double det = gradient_determinant(e);
  const double m = midpoint_determinant(e, det);
  const double hoop_scale = 1.0 / (1.0 + 0.5 * h);
  Vec5 result;
  result << (e11 + 0.5 * det) / m, (e22 + 0.5 * det) / m, h * hoop_scale, e12 / m, w / m;
  if (jacobian != nullptr) {
    Mat5& j = *jacobian;
    Vec5 d_det, d_m;
    d_det << e22, e11, 0.0, -e12, 2.0 * w;
    d_m = 0.25 * d_det;
    d_m[0] += 0.5;
    d_m[1] += 0.5;
    // Each in-plane row is (numerator' − result · m') / m.
    j.row(0) = (0.5 * d_det - result[0] * d_m).transpose() / m;
    j(0, 0) += 1.0 / m;
    j.row(1) = (0.5 * d_det - result[1] * d_m).transpose() / m;
    j(1, 1) += 1.0 / m;
    j.row(2).setZero();
    j(2, 2) = hoop_scale * hoop_scale;
    j.row(3) = (-result[3] * d_m).transpose() / m;
    j(3, 3) += 1.0 / m;
    j.row(4) = (-result[4] * d_m).transpose() / m;
    j(4, 4) += 1.0 / m;
  }
  return result;
}

}  // namespace pilempm::mpm::quasi_static::detail
