#pragma once
// Loops over the nodes of one particle's stencil (shape_functions.hpp), for the transfers between
// particles and grid of any scheme.
#include <type_traits>

#include "pilempm/mpm/shape_functions.hpp"

namespace pilempm::mpm {

/// Visits the nodes of one particle's stencil: visit(n, S_n, dS_n/dx, dS_n/dy) with n the node
/// index on a grid of `nx` nodes per row. The usual 3 x 3 stencil runs as a fixed loop the
/// compiler unrolls (no branch on the counts).
template <class NodeVisitor>
inline void for_each_node(const Stencil& stencil, int nx, NodeVisitor&& visit) {
  if (stencil.x.count == 3 && stencil.y.count == 3) {
    for (int j = 0; j < 3; ++j) {
      const int row = (stencil.y.first + j) * nx + stencil.x.first;
      const double weight_y = stencil.y.weight[j], gradient_y = stencil.y.gradient[j];
      for (int i = 0; i < 3; ++i) {
        visit(row + i, stencil.x.weight[i] * weight_y, stencil.x.gradient[i] * weight_y,
              stencil.x.weight[i] * gradient_y);
      }
    }
    return;
  }
  for (int j = 0; j < stencil.y.count; ++j) {
    const int row = (stencil.y.first + j) * nx + stencil.x.first;
    const double weight_y = stencil.y.weight[j], gradient_y = stencil.y.gradient[j];
    for (int i = 0; i < stencil.x.count; ++i) {
      visit(row + i, stencil.x.weight[i] * weight_y, stencil.x.gradient[i] * weight_y,
            stencil.x.weight[i] * gradient_y);
    }
  }
}

/// Visits the rows of one particle's stencil: visit(first node of the row, node count, S_j(y),
/// dS_j/dy), the count a compile-time 3 for the usual 3 x 3 stencil. Sums over a row first and
/// then over the rows take fewer products than node by node.
template <class RowVisitor>
inline void for_each_row(const Stencil& stencil, int nx, RowVisitor&& visit) {
  if (stencil.x.count == 3 && stencil.y.count == 3) {
    for (int j = 0; j < 3; ++j) {
      visit((stencil.y.first + j) * nx + stencil.x.first, std::integral_constant<int, 3>{},
            stencil.y.weight[j], stencil.y.gradient[j]);
    }
    return;
  }
  for (int j = 0; j < stencil.y.count; ++j) {
    visit((stencil.y.first + j) * nx + stencil.x.first, stencil.x.count, stencil.y.weight[j],
          stencil.y.gradient[j]);
  }
}

}  // namespace pilempm::mpm
