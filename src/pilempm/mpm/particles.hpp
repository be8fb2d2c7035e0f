#pragma once
// Material points stored as structure of arrays: each field is one contiguous vector, indexed by
// the particle number. In plane strain, mass and volume are per unit thickness; in axisymmetry
// (x = r, y = z) they are per radian, V_p = r_p A_p.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "pilempm/constitutive/material_state.hpp"
#include "pilempm/mpm/grid.hpp"

namespace pilempm::mpm {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

enum class Geometry {
  plane_strain,  ///< x, y in the plane; zero strain along z (Mandel component 33)
  axisymmetric,  ///< x = r, y = z; component 33 is the hoop direction θθ
};

/// One particle's initial data, for Particles::add.
struct ParticleInit {
  Vec2 position = Vec2::Zero();   ///< [m]
  Vec2 velocity = Vec2::Zero();   ///< [m/s]
  double mass = 0.0;              ///< [kg] (per unit thickness or per radian)
  double volume = 0.0;            ///< [m^3] (per unit thickness or per radian)
  Vec2 half_size = Vec2::Zero();  ///< GIMP half-lengths of the particle's domain [m]
  int material = 0;               ///< index into the solver's list of models
  MaterialState state;
};

struct Particles {
  std::vector<Vec2> position;              ///< [m]
  std::vector<Vec2> velocity;              ///< [m/s]
  std::vector<double> mass;                ///< [kg]
  std::vector<double> initial_volume;      ///< [m^3]
  std::vector<double> volume;              ///< current volume J V_0 [m^3]
  std::vector<Vec2> initial_half_size;     ///< GIMP half-lengths at creation [m]
  std::vector<Vec2> half_size;             ///< current GIMP half-lengths [m]
  std::vector<Mat2> deformation_gradient;  ///< in-plane F (xx, xy; yx, yy)
  /// F_33: 1 in plane strain, the hoop stretch r / r_0 in axisymmetry.
  std::vector<double> out_of_plane_stretch;
  std::vector<int> material;         ///< index into the solver's list of models
  std::vector<MaterialState> state;  ///< stress (Mandel, tension positive), void ratio, ...
  std::vector<Vec2> external_force;  ///< point load on the particle [N]

  std::size_t size() const { return position.size(); }
  void reserve(std::size_t count);
  /// Appends one particle with F = I; returns its index.
  std::size_t add(const ParticleInit& particle);
  /// Bytes of particle data per particle (the solver adds its per-particle scratch).
  static std::size_t bytes_per_particle();
};

/// cpGIMP: the half-lengths of a particle's domain that follow the stretch V = sqrt(F F^T) along
/// x and y from their initial values (the 2x2 square root sqrt(B) = (B + sqrt(det B) I) /
/// sqrt(tr B + 2 sqrt(det B)), B = F F^T).
inline Vec2 stretched_half_size(const Vec2& initial_half_size, const Mat2& deformation_gradient) {
  const Mat2 left_cauchy_green = deformation_gradient * deformation_gradient.transpose();
  const double root_det = std::abs(deformation_gradient.determinant());
  const double scale = 1.0 / std::sqrt(left_cauchy_green.trace() + 2.0 * root_det);
  return initial_half_size.cwiseProduct(Vec2((left_cauchy_green(0, 0) + root_det) * scale,
                                             (left_cauchy_green(1, 1) + root_det) * scale));
}

/// Scales a particle's deformation isotropically so that its volume ratio J = det F · λ_θ (the
/// hoop stretch λ_θ in axisymmetry; plane strain keeps it at 1 and scales F alone) is at most
/// `ratio`; the shape (F / J^(1/3), or / J^(1/2) in plane strain) is kept. Returns whether it
/// scaled. For sand on the stress floor (quasi_static::Settings::floor_volume_ratio).
inline bool limit_volume_ratio(Mat2& deformation_gradient, double& hoop_stretch, double ratio,
                               bool axisymmetric) {
  const double j = deformation_gradient.determinant() * (axisymmetric ? hoop_stretch : 1.0);
  if (!(j > ratio * (1.0 + 1e-12))) return false;  // at the limit to round-off: left alone
  const double scale = axisymmetric ? std::cbrt(ratio / j) : std::sqrt(ratio / j);
  deformation_gradient *= scale;
  if (axisymmetric) hoop_stretch *= scale;
  return true;
}

/// A rectangle to fill with particles, n_x × n_y per grid cell.
struct RectangleFill {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;  ///< [m]
  int particles_per_cell_x = 2;
  int particles_per_cell_y = 2;
  double density = 0.0;  ///< ρ [kg/m^3]
  int material = 0;
  MaterialState initial_state;
  Vec2 initial_velocity = Vec2::Zero();
};

/// Adds a particle at the centre of each sub-cell (a cell split n_x × n_y) whose centre lies in
/// the rectangle [x_min, x_max) × [y_min, y_max). Volume = sub-cell area (times r_p in
/// axisymmetry), mass = ρ V, half-sizes = half the sub-cell. Returns the number added; throws
/// InvalidValue for an empty rectangle, a non-positive density or count, or a rectangle outside
/// the grid (or reaching r < 0 in axisymmetry).
std::size_t fill_rectangle(Particles& particles, const Grid& grid, Geometry geometry,
                           const RectangleFill& fill);

}  // namespace pilempm::mpm
