#include "pilempm/mpm/grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "pilempm/core/error.hpp"

namespace pilempm::mpm {

GridAxis::GridAxis(std::vector<double> node_coordinates) : nodes_(std::move(node_coordinates)) {
  if (nodes_.size() < 2)
    throw InvalidValue("grid axis node count", std::to_string(nodes_.size()), ">= 2");
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!std::isfinite(nodes_[i]))
      throw InvalidValue("grid node coordinate", format_value(nodes_[i]), "finite");
    if (i > 0 && !(nodes_[i] > nodes_[i - 1]))
      throw InvalidValue("grid node coordinate " + std::to_string(i), format_value(nodes_[i]),
                         "> the previous node " + format_value(nodes_[i - 1]));
  }
  const double length = end() - start();
  const double mean_spacing = length / cell_count();
  min_spacing_ = length;
  double max_deviation = 0.0;
  inverse_spacings_.resize(static_cast<std::size_t>(cell_count()));
  for (int c = 0; c < cell_count(); ++c) {
    inverse_spacings_[c] = 1.0 / spacing(c);
    min_spacing_ = std::min(min_spacing_, spacing(c));
    max_deviation = std::max(max_deviation, std::abs(spacing(c) - mean_spacing));
  }
  uniform_ = max_deviation <= 1e-10 * mean_spacing;
  if (uniform_) inverse_spacing_ = cell_count() / length;
}

GridAxis GridAxis::uniform(double start, double end, int cells) {
  if (cells < 1) throw InvalidValue("grid cell count", std::to_string(cells), ">= 1");
  if (!(end > start))
    throw InvalidValue("grid axis end", format_value(end), "> start " + format_value(start));
  std::vector<double> nodes(static_cast<std::size_t>(cells) + 1);
  for (int i = 0; i <= cells; ++i) nodes[i] = start + (end - start) * i / cells;
  nodes.back() = end;
  return GridAxis(std::move(nodes));
}

namespace {

// Spacings of the cells leaving a fine band over `distance`: fine_spacing * ratio^k (capped),
// the last one dropped when it would overshoot by more than half, then all scaled to fit.
std::vector<double> growing_spacings(double distance, double fine_spacing, double ratio,
                                     double max_spacing) {
  std::vector<double> spacings;
  if (distance <= 0.0) return spacings;
  double sum = 0.0, next = fine_spacing;
  while (sum < distance) {
    next = std::min(next * ratio, max_spacing);
    spacings.push_back(next);
    sum += next;
  }
  if (spacings.size() > 1 && sum - distance > 0.5 * spacings.back()) {
    sum -= spacings.back();
    spacings.pop_back();
  }
  for (double& s : spacings) s *= distance / sum;
  return spacings;
}

}  // namespace

GridAxis GridAxis::graded(double start, double end, double band_start, double band_end,
                          double fine_spacing, double growth_ratio, double max_spacing) {
  if (!(band_start >= start && band_start < band_end && band_end <= end))
    throw InvalidValue(
        "graded grid band", format_value(band_start) + " .. " + format_value(band_end),
        "inside [" + format_value(start) + ", " + format_value(end) + "] with start < end");
  if (!(fine_spacing > 0.0 && std::isfinite(fine_spacing)))
    throw InvalidValue("graded grid fine spacing", format_value(fine_spacing), "> 0");
  if (!(growth_ratio >= 1.0 && std::isfinite(growth_ratio)))
    throw InvalidValue("graded grid growth ratio", format_value(growth_ratio), ">= 1");
  if (!(max_spacing >= fine_spacing))
    throw InvalidValue("graded grid max spacing", format_value(max_spacing),
                       ">= the fine spacing " + format_value(fine_spacing));

  const int band_cells =
      std::max(1, static_cast<int>(std::lround((band_end - band_start) / fine_spacing)));
  const double band_spacing = (band_end - band_start) / band_cells;
  const std::vector<double> left =
      growing_spacings(band_start - start, band_spacing, growth_ratio, max_spacing);
  const std::vector<double> right =
      growing_spacings(end - band_end, band_spacing, growth_ratio, max_spacing);

  std::vector<double> nodes;
  nodes.reserve(left.size() + static_cast<std::size_t>(band_cells) + right.size() + 1);
  // Left cells, outermost first: node positions measured back from the band's start.
  std::vector<double> left_nodes(left.size());
  double x = band_start;
  for (std::size_t k = 0; k < left.size(); ++k) left_nodes[k] = (x -= left[k]);
  if (!left_nodes.empty()) left_nodes.back() = start;
  nodes.insert(nodes.end(), left_nodes.rbegin(), left_nodes.rend());
  for (int k = 0; k < band_cells; ++k) nodes.push_back(band_start + band_spacing * k);
  nodes.push_back(band_end);
  x = band_end;
  for (double s : right) nodes.push_back(x += s);
  if (!right.empty()) nodes.back() = end;
  return GridAxis(std::move(nodes));
}

int GridAxis::graded_cell_of(double x) const {
  const auto above = std::upper_bound(nodes_.begin(), nodes_.end(), x);
  const int c = static_cast<int>(above - nodes_.begin()) - 1;
  return std::clamp(c, 0, cell_count() - 1);
}

void NodalFields::resize(int node_count) {
  const auto n = static_cast<std::size_t>(node_count);
  for (std::vector<double>* field :
       {&mass, &momentum_x, &momentum_y, &force_x, &force_y, &velocity_x, &velocity_y,
        &velocity_change_x, &velocity_change_y})
    field->assign(n, 0.0);
}

Grid::Grid(GridAxis x_axis, GridAxis y_axis)
    : x_axis_(std::move(x_axis)), y_axis_(std::move(y_axis)) {
  boundaries_.fill(BoundaryCondition::free);
  nodes_.resize(node_count());
  update_constraints();
}

double Grid::min_spacing() const {
  return std::min(x_axis_.min_spacing(), y_axis_.min_spacing());
}

bool Grid::contains(double x, double y) const {
  return x >= x_axis_.start() && x <= x_axis_.end() && y >= y_axis_.start() && y <= y_axis_.end();
}

void Grid::set_boundary(Side side, BoundaryCondition condition) {
  boundaries_[static_cast<int>(side)] = condition;
  update_constraints();
}

void Grid::set_axis_of_symmetry(bool on_left) {
  if (on_left && x_axis_.start() != 0.0)
    throw InvalidValue("grid x start for an axis of symmetry", format_value(x_axis_.start()), "0");
  axis_of_symmetry_ = on_left;
  update_constraints();
}

void Grid::update_constraints() {
  const int columns = nx(), rows = ny();
  free_x_.assign(static_cast<std::size_t>(node_count()), 1.0);
  free_y_.assign(static_cast<std::size_t>(node_count()), 1.0);
  // The component normal to a side: x on left and right, y on bottom and top.
  auto constrain = [](BoundaryCondition condition, int first, int count, int stride,
                      std::vector<double>& normal, std::vector<double>& tangential) {
    if (condition == BoundaryCondition::free) return;
    for (int k = 0, n = first; k < count; ++k, n += stride) {
      normal[n] = 0.0;
      if (condition == BoundaryCondition::fixed) tangential[n] = 0.0;
    }
  };
  BoundaryCondition left = boundary(Side::left);
  if (axis_of_symmetry_ && left == BoundaryCondition::free) left = BoundaryCondition::roller;
  constrain(left, 0, rows, columns, free_x_, free_y_);
  constrain(boundary(Side::right), columns - 1, rows, columns, free_x_, free_y_);
  constrain(boundary(Side::bottom), 0, columns, 1, free_y_, free_x_);
  constrain(boundary(Side::top), (rows - 1) * columns, columns, 1, free_y_, free_x_);
}

void Grid::apply_boundary_conditions(double* field_x, double* field_y) const {
  for (int n = 0; n < node_count(); ++n) {
    field_x[n] *= free_x_[n];
    field_y[n] *= free_y_[n];
  }
}

}  // namespace pilempm::mpm
