#include "pilempm/mpm/shape_functions.hpp"

#include <algorithm>

namespace pilempm::mpm {

namespace {

void linear_weights_in_cell(const double* node, const double* inverse_spacing, int cell, double x,
                            AxisWeights& out) {
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

}  // namespace

void linear_weights(const GridAxis& axis, double x, AxisWeights& out) {
  linear_weights_in_cell(axis.nodes().data(), axis.inverse_spacings().data(), axis.cell_of(x), x,
                         out);
  pad_to_three_nodes(axis.node_count(), out);
}

void gimp_weights(const GridAxis& axis, double x, double half_size, AxisWeights& out) {
  const double* node = axis.nodes().data();
  const double* inverse_spacing = axis.inverse_spacings().data();
  const int cells = axis.cell_count();
  const int cell = axis.cell_of(x);
  // Shrink the domain symmetrically so that it stays inside the grid and the cells next to x's.
  const double reach_left = x - node[std::max(cell - 1, 0)];
  const double reach_right = node[std::min(cell + 2, cells)] - x;
  const double half = std::min(half_size, std::min(reach_left, reach_right));
  if (!(half > 1e-12 * (node[cell + 1] - node[cell]))) {  // a point: the hat functions
    linear_weights_in_cell(node, inverse_spacing, cell, x, out);
    pad_to_three_nodes(axis.node_count(), out);
    return;
  }
  const double a = x - half, b = x + half;
  if (a >= node[cell] && b <= node[cell + 1]) {
    // The domain lies in one cell, where the hats are linear: their mean over the domain is their
    // value at x, and (N_i(b) - N_i(a)) / (2l) their slope.
    linear_weights_in_cell(node, inverse_spacing, cell, x, out);
    pad_to_three_nodes(axis.node_count(), out);
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
  pad_to_three_nodes(axis.node_count(), out);
}

void compute_stencil(const Grid& grid, ShapeFunction kind, double x, double y, double half_x,
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
