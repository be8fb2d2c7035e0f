#pragma once
// Shape functions of the particle-grid transfers on a rectilinear grid: the tensor product of
// 1D weights along x and y.
//
//  * linear: the hat functions N_i of the cell that holds the particle (for verification; the
//    gradients jump when a particle crosses a cell boundary).
//  * GIMP (generalized interpolation material point, Bardenhagen & Kober 2004, CMES 5(6)): the
//    hat function averaged over the particle's domain [x_p - l, x_p + l],
//      S_i(x_p) = 1/(2l) ∫ N_i(x) dx,   dS_i/dx_p = (N_i(x_p + l) - N_i(x_p - l)) / (2l),
//    integrated exactly cell by cell, so it holds on graded grids where the hat functions are not
//    symmetric. uGIMP keeps l at its initial value; cpGIMP stretches it with the material.
//
// The particle domain is kept inside the grid and inside the cells next to the particle's own
// cell by shrinking l symmetrically where needed; then every weight is continuous in x_p (as long
// as l does not exceed the neighbouring cells), the weights sum to one, and a linear field is
// reproduced exactly. At most 4 nodes per axis carry weight (3 when l is at most half a cell).
#include <algorithm>

#include "pilempm/mpm/grid.hpp"

namespace pilempm::mpm {

enum class ShapeFunction { linear, ugimp, cpgimp };

/// The weights of one particle along one axis, for the nodes first .. first + count - 1. Where
/// the axis has at least 3 nodes, a stencil of 2 nodes is padded to 3 with a zero weight, so that
/// count is 3 in the usual case and 4 only for a domain over three cells.
struct AxisWeights {
  static constexpr int kMaxNodes = 4;
  int first = 0;
  int count = 0;
  double weight[kMaxNodes] = {};
  double gradient[kMaxNodes] = {};  ///< dS/dx_p [1/m]
};

/// Linear hat functions at x.
inline void linear_weights(const GridAxis& axis, double x, AxisWeights& out);

/// GIMP weights at x for a particle of half-length `half_size` [m].
inline void gimp_weights(const GridAxis& axis, double x, double half_size, AxisWeights& out);

/// The 2D weights S_ij = S_i(x) S_j(y) with gradient (dS_i/dx S_j, S_i dS_j/dy).
struct Stencil {
  AxisWeights x, y;
};

/// The stencil of a particle at (x, y) with GIMP half-sizes (half_x, half_y), ignored for linear.
inline void compute_stencil(const Grid& grid, ShapeFunction kind, double x, double y, double half_x,
                            double half_y, Stencil& out);

// Definitions (inline: they run in the innermost particle loop).

namespace detail {

inline void linear_weights_in_cell(const double* node, const double* inverse_spacing, int cell,
                                   double x, AxisWeights& out) {
  const double inverse = inverse_spacing[cell];
  out.first = cell;
  out.count = 2;
  out.weight[0] = (node[cell + 1] - x) * inverse;
  out.weight[1] = (x - node[cell]) * inverse;
  out.gradient[0] = -inverse;
  out.gradient[1] = inverse;
  out.weight[2] = out.weight[3] = out.gradient[2] = out.gradient[3] = 0.0;
}

// Pads a 2-node stencil to 3 nodes with a zero weight (inside the axis), so that the particle
// loops can run a fixed 3 x 3 stencil in the usual case instead of branching on the count.
inline void pad_to_three_nodes(int node_count, AxisWeights& out) {
  if (out.count != 2 || node_count < 3) return;
  out.count = 3;
  if (out.first + 2 < node_count) return;  // zero third node: already zero
  --out.first;                             // at the end of the axis: zero first node instead
  out.weight[2] = out.weight[1];
  out.weight[1] = out.weight[0];
  out.weight[0] = 0.0;
  out.gradient[2] = out.gradient[1];
  out.gradient[1] = out.gradient[0];
  out.gradient[0] = 0.0;
}

}  // namespace detail

inline void linear_weights(const GridAxis& axis, double x, AxisWeights& out) {
  detail::linear_weights_in_cell(axis.nodes().data(), axis.inverse_spacings().data(),
                                 axis.cell_of(x), x, out);
  detail::pad_to_three_nodes(axis.node_count(), out);
}

[[gnu::always_inline]] inline void gimp_weights(const GridAxis& axis, double x, double half_size,
                                                AxisWeights& out) {
  const double* node = axis.nodes().data();
  const double* inverse_spacing = axis.inverse_spacings().data();
  const int cells = axis.cell_count();
  const int cell = axis.cell_of(x);
  // Shrink the domain symmetrically so that it stays inside the grid and the cells next to x's.
  const double reach_left = x - node[std::max(cell - 1, 0)];
  const double reach_right = node[std::min(cell + 2, cells)] - x;
  const double half = std::min(half_size, std::min(reach_left, reach_right));
  if (!(half > 1e-12 * (node[cell + 1] - node[cell]))) {  // a point: the hat functions
    detail::linear_weights_in_cell(node, inverse_spacing, cell, x, out);
    detail::pad_to_three_nodes(axis.node_count(), out);
    return;
  }
  const double a = x - half, b = x + half;
  if (a >= node[cell] && b <= node[cell + 1]) {
    // The domain lies in one cell, where the hats are linear: their mean over the domain is their
    // value at x, and (N_i(b) - N_i(a)) / (2l) their slope.
    detail::linear_weights_in_cell(node, inverse_spacing, cell, x, out);
    detail::pad_to_three_nodes(axis.node_count(), out);
    return;
  }
  const int first_cell = a < node[cell] ? cell - 1 : cell;
  const int last_cell = b > node[cell + 1] ? cell + 1 : cell;
  out.first = first_cell;
  out.count = last_cell - first_cell + 2;
  for (int k = 0; k < AxisWeights::kMaxNodes; ++k) out.weight[k] = out.gradient[k] = 0.0;

  const double inverse_length = 1.0 / (b - a);  // 1/(2l), with the rounding of a and b
  for (int c = first_cell; c <= last_cell; ++c) {
    // Overlap [u, v] of the domain with cell c, where the hats of nodes c and c+1 are linear:
    // their integral is the overlap length times their value at the overlap's midpoint.
    const double u = std::max(a, node[c]), v = std::min(b, node[c + 1]);
    const double scale = (v - u) * inverse_length * inverse_spacing[c];
    const double middle = 0.5 * (u + v);
    out.weight[c - first_cell] += scale * (node[c + 1] - middle);
    out.weight[c - first_cell + 1] += scale * (middle - node[c]);
  }
  // dS_i/dx_p = (N_i(b) - N_i(a)) / (2l): the hats at the two ends of the domain.
  const double scale_b = inverse_length * inverse_spacing[last_cell];
  const double scale_a = inverse_length * inverse_spacing[first_cell];
  const int last = last_cell - first_cell;
  out.gradient[last] += scale_b * (node[last_cell + 1] - b);
  out.gradient[last + 1] += scale_b * (b - node[last_cell]);
  out.gradient[0] -= scale_a * (node[first_cell + 1] - a);
  out.gradient[1] -= scale_a * (a - node[first_cell]);
  detail::pad_to_three_nodes(axis.node_count(), out);
}

inline void compute_stencil(const Grid& grid, ShapeFunction kind, double x, double y, double half_x,
                            double half_y, Stencil& out) {
  if (kind == ShapeFunction::linear) {
    linear_weights(grid.x_axis(), x, out.x);
    linear_weights(grid.y_axis(), y, out.y);
  } else {
    gimp_weights(grid.x_axis(), x, half_x, out.x);
    gimp_weights(grid.y_axis(), y, half_y, out.y);
  }
}

}  // namespace pilempm::mpm
