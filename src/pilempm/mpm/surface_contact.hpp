#pragma once
// Frictional penalty contact between a point of the soil and the exact surface of a rigid body,
// shared by the quasi-static solver (in its Newton iterations) and the explicit solver (contact =
// "surface", once per step).
//
// At a contact point q (a corner of a particle's GIMP domain) with gap g = signed distance to the
// body's surface (< 0: inside) and outward normal n, the force on the soil is
//   F = f_n n + f_t t,   t = (−n_y, n_x),
// with the normal force of the penetration p = max(−g, 0), smoothed over a depth δ so that it is
// continuously differentiable where a point enters contact (a kink there makes the Newton
// iterations of the quasi-static solver chatter, docs/quasi-static.md):
//   f_n = k_n p² / (2δ)  for p < δ,   f_n = k_n (p − δ/2)  beyond   (δ = 0: f_n = k_n p),
// with the tangential force from a return map on the trial force (Wriggers 2006, Computational
// Contact Mechanics, §5.2, the penalty regularisation of Coulomb's law):
//   f_t^trial = f_t,n − k_t (Δs · t),   Δs the slip of the point relative to the body over the
//   step, stick: |f_t^trial| <= μ f_n  ->  f_t = f_t^trial;   slip: f_t = μ f_n sign(f_t^trial).
// Its stiffness K = −∂F/∂Δs (for the Newton matrix):
//   stick: k n n^T + k_t t t^T;   slip: k n n^T + μ k sign(f_t^trial) t n^T (not symmetric),
// k = ∂f_n/∂p (k_n p/δ within the smoothing depth, k_n beyond), plus, where the surface is
// curved (κ: ∂n/∂x = κ t t^T, so ∂t/∂x = −κ n t^T; a rounded vertex), the turning of the force
// with the normal:
//   κ (−f_n t t^T + f_t n t^T),   and in stick κ ((f_t,n − k_t Δs) · n) t t^T
// (the trial force's projection turning with t). The first term is negative: a point pressed
// onto a convex corner is pushed on along the surface when it moves along it.
#include <algorithm>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/mpm/particles.hpp"

namespace pilempm::mpm {

struct ContactSettings {
  /// Penalty factor β: the normal stiffness of a point is k_n = β M_p A_q / d_p, M_p the
  /// particle's constrained modulus (ConstitutiveModel::wave_modulus), A_q the point's share of
  /// the domain's boundary (l_x + l_y, times r_q in axisymmetry), d_p = 2 min(l_x⁰, l_y⁰) the
  /// particle's size at creation (see corner_normal_stiffness). The penetration under a contact
  /// stress σ_c is about σ_c d_p / (β M_p).
  double penalty_factor = 2.0;
  /// k_t = tangential_ratio · k_n.
  double tangential_ratio = 0.1;
  /// The smoothing depth δ of the normal force, as a fraction of the particle size d_p (at
  /// creation, as in k_n; 0: the kinked law f_n = k_n p).
  double smoothing = 0.0;
  /// Points closer than this fraction of the particle size outside the surface carry the stick
  /// stiffness in the first Newton matrix of an increment, without force (see penalty_contact).
  double stiffness_margin = 0.01;
  /// The bodies' vertices are rounded by this fraction of the grid's smallest spacing, so that
  /// the normal turns continuously around a vertex for penetrated points too (0: sharp, the
  /// default: on the pile, 0.25 made the Newton iterations fail at 0.5 D, docs/quasi-static.md).
  double vertex_radius = 0.0;
  /// Whether the quasi-static Newton matrix holds the turning of the force with the normal at
  /// a rounded vertex (the κ terms of penalty_contact). They make the matrix the residual's
  /// derivative (the contact part of QuasiStaticSolver::check_tangent from 10⁻⁵–10⁻² to 10⁻⁹ on
  /// the hypoplastic pile) but slow Newton down: their leading part −f_n κ t t^T is a negative
  /// stiffness along the surface, and the hypoplastic pile push took 1 280 iterations and 6 cuts
  /// with them against 1 041 and 2 without (the quick case 1 114 and 7 against 988 and 4),
  /// docs/quasi-static.md. Off: left out, by default.
  bool turning_terms = false;

  /// Throws InvalidValue naming the first setting out of range.
  void validate() const;
};

/// What a contact point carries from one converged step to the next.
struct ContactHistory {
  Vec2 tangential_force = Vec2::Zero();  ///< on the soil [N]
  int body = -1;                         ///< the body it touches (-1: none)
};

struct PointContact {
  bool active = false;
  bool slip = false;
  Vec2 force = Vec2::Zero();              ///< on the soil [N]
  Mat2 stiffness = Mat2::Zero();          ///< −∂F/∂Δs [N/m]
  double normal_force = 0.0;              ///< f_n [N]
  double tangential_force = 0.0;          ///< f_t [N] along t
  Vec2 tangential_vector = Vec2::Zero();  ///< f_t t [N]
};

/// The penalty law at one point; `previous_tangential_force` is the history's force (projected
/// on the current tangent). A point just outside, 0 <= gap < margin, carries no force but the
/// stick stiffness k_n n n^T + k_t t t^T, so that a body resting on a surface with zero gap (or
/// an iterate that has just left it) does not leave the Newton matrix singular; it changes the
/// path of the iterations, not their solution.
PointContact penalty_contact(double gap, const Vec2& normal, const Vec2& slip_increment,
                             const Vec2& previous_tangential_force, double normal_stiffness,
                             double tangential_stiffness, double friction, double margin = 0.0,
                             double smoothing = 0.0, double curvature = 0.0);

/// The particle size d_p = 2 min(l_x⁰, l_y⁰) of the penalty law: that of the domain at creation,
/// not the current one. A cpGIMP domain follows the stretch, and the sand that a pile pushes from
/// the axis to its shaft is squeezed radially to a sliver (radial stretch r₀/r → 0): with the
/// current size its corners' stiffness grew by the squeeze, without bound, and their smoothing
/// depth shrank with it; a perturbation of 10⁻⁴ of a Newton step then moved such a corner's
/// force by newtons on the full model MPM-2 (docs/quasi-static.md, "Contact with the exact
/// surface").
inline double penalty_length(const Vec2& initial_half_size) {
  return 2.0 * std::min(initial_half_size.x(), initial_half_size.y());
}

/// k_n = β M_c A_q / d_p of a corner at radius (or 1 in plane strain) `lever`: A_q = (l_x + l_y)
/// lever from the current half-lengths l, d_p = penalty_length() of the initial ones (passed in:
/// the caller needs it for the smoothing depth too).
inline double corner_normal_stiffness(double penalty_factor, double modulus, const Vec2& half_size,
                                      double length, double lever) {
  return penalty_factor * modulus * (half_size.x() + half_size.y()) * lever / length;
}

/// The penalty modulus M_c of each material (in k_n = β M_c A_q / d_p): the largest wave modulus
/// of its particles at their current state (0 for a material without particles). Both analyses
/// fix it at their first step, so that the force of an unchanged penetration does not follow the
/// sand's stiffening (docs/quasi-static.md, "Contact with the exact surface").
std::vector<double> penalty_moduli(const Particles& particles, const std::vector<ModelPtr>& models);

}  // namespace pilempm::mpm
