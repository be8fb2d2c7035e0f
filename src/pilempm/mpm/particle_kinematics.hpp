#pragma once
// The kinematics of a particle from a nodal vector field, for any scheme: the explicit solver
// passes the nodal velocities (and multiplies by the step), a quasi-static one would pass the
// nodal displacement increments.
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

/// The gradient of a nodal vector field u at a particle, ∂u_a/∂x_b = Σ_i u_ia ∂S_i/∂x_b, and the
/// field's x (radial) component there, Σ_i S_i u_ix (the hoop strain in axisymmetry is its
/// increment over r).
struct FieldGradient {
  double dux_dx = 0.0, dux_dy = 0.0, duy_dx = 0.0, duy_dy = 0.0;
  double radial = 0.0;
};

/// FieldGradient of the nodal field `field(n)` (a Vec2 of node n) over one particle's stencil,
/// summed row by row: along a row Σ S_x' u and Σ S_x u, then times S_y or S_y'.
template <class NodalField>
inline FieldGradient gradient_at_particle(const Stencil& stencil, int nx, NodalField&& field) {
  FieldGradient result;
  for_each_row(stencil, nx, [&](int row, auto row_nodes, double weight_y, double gradient_y) {
    Vec2 gradient_u = Vec2::Zero(), weight_u = Vec2::Zero();
    for (int k = 0; k < row_nodes; ++k) {
      const Vec2& u = field(row + k);
      gradient_u += stencil.x.gradient[k] * u;
      weight_u += stencil.x.weight[k] * u;
    }
    result.dux_dx += weight_y * gradient_u.x();
    result.dux_dy += gradient_y * weight_u.x();
    result.duy_dx += weight_y * gradient_u.y();
    result.duy_dy += gradient_y * weight_u.y();
    result.radial += weight_y * weight_u.x();
  });
  return result;
}

}  // namespace pilempm::mpm
