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
void linear_weights(const GridAxis& axis, double x, AxisWeights& out);

/// GIMP weights at x for a particle of half-length `half_size` [m].
void gimp_weights(const GridAxis& axis, double x, double half_size, AxisWeights& out);

/// The 2D weights S_ij = S_i(x) S_j(y) with gradient (dS_i/dx S_j, S_i dS_j/dy).
struct Stencil {
  AxisWeights x, y;
};

/// The stencil of a particle at (x, y) with GIMP half-sizes (half_x, half_y), ignored for linear.
void compute_stencil(const Grid& grid, ShapeFunction kind, double x, double y, double half_x,
                     double half_y, Stencil& out);

}  // namespace pilempm::mpm
