#include "pilempm/mpm/explicit/grid_update.hpp"

#include "pilempm/mpm/solver.hpp"

namespace pilempm::mpm {

void dashpot_coefficients(const Grid& grid, const SolverSettings& settings,
                          std::vector<double>& dashpot_x, std::vector<double>& dashpot_y) {
  const auto nodes = static_cast<std::size_t>(grid.node_count());
  dashpot_x.assign(settings.absorbing_boundaries.empty() ? 0 : nodes, 0.0);
  dashpot_y.assign(settings.absorbing_boundaries.empty() ? 0 : nodes, 0.0);
  const bool axisymmetric = settings.geometry == Geometry::axisymmetric;
  const GridAxis& x_axis = grid.x_axis();
  const GridAxis& y_axis = grid.y_axis();
  // The share of a side's length that node k of an axis carries: half of each adjacent cell.
  auto share = [](const GridAxis& axis, int k) {
    double length = 0.0;
    if (k > 0) length += 0.5 * axis.spacing(k - 1);
    if (k < axis.cell_count()) length += 0.5 * axis.spacing(k);
    return length;
  };
  for (const AbsorbingBoundary& boundary : settings.absorbing_boundaries) {
    const double normal = boundary.density * boundary.p_wave_speed;
    const double tangential = boundary.density * boundary.s_wave_speed;
    const bool vertical_side = boundary.side == Side::left || boundary.side == Side::right;
    if (vertical_side) {
      const int i = boundary.side == Side::left ? 0 : grid.nx() - 1;
      const double radius = axisymmetric ? x_axis.node(i) : 1.0;
      for (int j = 0; j < grid.ny(); ++j) {
        const double area = share(y_axis, j) * radius;
        dashpot_x[static_cast<std::size_t>(grid.node_index(i, j))] += normal * area;
        dashpot_y[static_cast<std::size_t>(grid.node_index(i, j))] += tangential * area;
      }
    } else {
      const int j = boundary.side == Side::bottom ? 0 : grid.ny() - 1;
      for (int i = 0; i < grid.nx(); ++i) {
        // Per radian in axisymmetry: the ring of radius r_i over the node's share of the side
        // (exact for the integral of r over a linear hat would differ by O(h^2 / r)).
        const double area = share(x_axis, i) * (axisymmetric ? x_axis.node(i) : 1.0);
        dashpot_x[static_cast<std::size_t>(grid.node_index(i, j))] += tangential * area;
        dashpot_y[static_cast<std::size_t>(grid.node_index(i, j))] += normal * area;
      }
    }
  }
}

}  // namespace pilempm::mpm
