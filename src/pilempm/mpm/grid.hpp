#pragma once
// The structured rectilinear background grid of the material point method: a 2D tensor-product
// grid whose two axes are each given by their node coordinates, uniform or graded (fine near the
// pile, coarse far away). x is the horizontal axis (the radius r in axisymmetry), y the vertical
// one (z in axisymmetry); gravity acts along -y. Node (i, j) has the index j * nx + i.
#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace pilempm::mpm {

/// One axis of the grid: strictly increasing node coordinates [m].
class GridAxis {
 public:
  /// Throws InvalidValue unless there are at least two finite, strictly increasing coordinates.
  explicit GridAxis(std::vector<double> node_coordinates);

  /// `cells` equal cells from `start` to `end`.
  static GridAxis uniform(double start, double end, int cells);

  /// A fine band [band_start, band_end] with cells of about `fine_spacing` (adjusted to fit the
  /// band exactly), and outside it cells growing geometrically by `growth_ratio` (>= 1) per cell
  /// up to `max_spacing`, towards `start` and `end`. The outer cells are scaled together so that
  /// they end exactly at `start` and `end`, so the growth ratio holds up to that scaling.
  static GridAxis graded(double start, double end, double band_start, double band_end,
                         double fine_spacing, double growth_ratio,
                         double max_spacing = std::numeric_limits<double>::infinity());

  int node_count() const { return static_cast<int>(nodes_.size()); }
  int cell_count() const { return node_count() - 1; }
  double node(int i) const { return nodes_[i]; }
  const std::vector<double>& nodes() const { return nodes_; }
  double start() const { return nodes_.front(); }
  double end() const { return nodes_.back(); }
  double spacing(int cell) const { return nodes_[cell + 1] - nodes_[cell]; }
  /// 1 / spacing(cell), stored.
  double inverse_spacing(int cell) const { return inverse_spacings_[cell]; }
  const std::vector<double>& inverse_spacings() const { return inverse_spacings_; }
  double min_spacing() const { return min_spacing_; }
  bool is_uniform() const { return uniform_; }

  /// The cell [x_c, x_c+1) that holds x; clamped to the first or last cell outside the axis, and
  /// the last cell holds the end node. O(1) on a uniform axis, binary search on a graded one.
  int cell_of(double x) const {
    const int last_cell = cell_count() - 1;
    if (uniform_) {
      const double position = (x - nodes_.front()) * inverse_spacing_;
      int c = position <= 0.0 ? 0 : static_cast<int>(std::min(position, double(last_cell)));
      // The coordinates are stored, not recomputed: settle round-off at a node against them.
      if (c > 0 && x < nodes_[c]) --c;
      if (c < last_cell && x >= nodes_[c + 1]) ++c;
      return c;
    }
    return graded_cell_of(x);
  }

 private:
  int graded_cell_of(double x) const;

  std::vector<double> nodes_;
  std::vector<double> inverse_spacings_;
  bool uniform_ = false;
  double inverse_spacing_ = 0.0;  // uniform axes only
  double min_spacing_ = 0.0;
};

/// A side of the rectangular grid.
enum class Side { left, right, bottom, top };

/// What a side prescribes at its nodes.
enum class BoundaryCondition {
  free,    ///< nothing
  roller,  ///< the velocity normal to the side is zero
  fixed,   ///< both velocity components are zero
};

/// Nodal fields as structure of arrays, one entry per node (index j * nx + i). Momentum and
/// forces are per unit thickness in plane strain and per radian in axisymmetry.
struct NodalFields {
  std::vector<double> mass;                                  ///< [kg]
  std::vector<double> momentum_x, momentum_y;                ///< [kg m/s]
  std::vector<double> force_x, force_y;                      ///< internal + external [N]
  std::vector<double> velocity_x, velocity_y;                ///< after the grid update [m/s]
  std::vector<double> velocity_change_x, velocity_change_y;  ///< over the step [m/s]

  void resize(int node_count);
};

class Grid {
 public:
  Grid(GridAxis x_axis, GridAxis y_axis);

  const GridAxis& x_axis() const { return x_axis_; }
  const GridAxis& y_axis() const { return y_axis_; }
  int nx() const { return x_axis_.node_count(); }
  int ny() const { return y_axis_.node_count(); }
  int node_count() const { return nx() * ny(); }
  int node_index(int i, int j) const { return j * nx() + i; }
  /// Smallest cell spacing along either axis [m].
  double min_spacing() const;
  /// Whether (x, y) lies inside the grid's rectangle (boundary included).
  bool contains(double x, double y) const;

  void set_boundary(Side side, BoundaryCondition condition);
  BoundaryCondition boundary(Side side) const { return boundaries_[static_cast<int>(side)]; }
  /// Marks the left side as the axis of symmetry r = 0 (axisymmetry): its radial velocity is
  /// zero whatever its boundary condition. Throws InvalidValue unless the grid starts at x = 0.
  void set_axis_of_symmetry(bool on_left);
  bool axis_of_symmetry() const { return axis_of_symmetry_; }

  /// Per node, 1 where the x (y) velocity is free and 0 where a side constrains it, from the
  /// boundary conditions and the axis of symmetry.
  const std::vector<double>& free_x() const { return free_x_; }
  const std::vector<double>& free_y() const { return free_y_; }
  /// Zeroes the constrained components of a nodal vector field.
  void apply_boundary_conditions(double* field_x, double* field_y) const;

  NodalFields& nodes() { return nodes_; }
  const NodalFields& nodes() const { return nodes_; }

 private:
  GridAxis x_axis_, y_axis_;
  void update_constraints();

  std::array<BoundaryCondition, 4> boundaries_{};
  bool axis_of_symmetry_ = false;
  std::vector<double> free_x_, free_y_;
  NodalFields nodes_;
};

}  // namespace pilempm::mpm
