// The set-up of a quasi-static sub-increment, shared by its Newton iterations: the particles'
// stencils, the unknowns, the ghost springs of weakly supported nodes, the cells' volumetric
// averaging, the rigid surfaces, and the Newton matrix's fixed pattern with its scatter maps.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/quasi_static/step_data.hpp"

namespace pilempm::mpm::quasi_static {

using namespace detail;

void QuasiStaticSolver::build_setup(StepSetup& setup) const {
  const Particles& p = particles_;
  const std::size_t count = p.size();
  const int nx = grid_.nx(), nodes = grid_.node_count();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  setup.nodes.resize(count);
  std::vector<double> support(std::size_t(nodes), 0.0);
  std::vector<int> reached_by(std::size_t(nodes), 0);  // particles with a weight at the node
  for (std::size_t i = 0; i < count; ++i) {
    Stencil stencil;
    compute_stencil(grid_, settings_.shape_function, p.position[i].x(), p.position[i].y(),
                    p.half_size[i].x(), p.half_size[i].y(), stencil);
    flatten(stencil, nx, setup.nodes[i]);
    const ParticleNodes& pn = setup.nodes[i];
    for (int k = 0; k < pn.count; ++k) {
      support[std::size_t(pn.node[k])] += pn.weight[k] * p.volume[i];
      if (pn.weight[k] > 0.0) ++reached_by[std::size_t(pn.node[k])];
    }
  }
  // Every node a particle reaches carries the unknowns of its free components; the weakly
  // supported ones get ghost springs to their better supported neighbours.
  std::vector<double> modulus(std::size_t(nodes), 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    const double m = materials_[std::size_t(p.material[i])]->wave_modulus(p.state[i]);
    const ParticleNodes& pn = setup.nodes[i];
    for (int k = 0; k < pn.count; ++k)
      if (pn.weight[k] > 0.0)
        modulus[std::size_t(pn.node[k])] = std::max(modulus[std::size_t(pn.node[k])], m);
  }
  setup.active.assign(std::size_t(nodes), 0);
  setup.dof.assign(2 * std::size_t(nodes), -1);
  setup.unknowns = 0;
  setup.ghosts.clear();
  // The larger of 1 - s_i / (threshold v_i) and 1 - n_i / support_particles, or 0.
  std::vector<double> weakness(std::size_t(nodes), 0.0);
  const int fewest = settings_.support_particles;
  const auto& free_x = grid_.free_x();
  const auto& free_y = grid_.free_y();
  for (int j = 0; j < grid_.ny(); ++j)
    for (int i = 0; i < nx; ++i) {
      const int n = grid_.node_index(i, j);
      if (!(support[std::size_t(n)] > 0.0)) continue;
      double x0, x1, y0, y1;
      node_share(grid_.x_axis(), i, x0, x1);
      node_share(grid_.y_axis(), j, y0, y1);
      const double own = (y1 - y0) * (axisymmetric ? 0.5 * (x1 * x1 - x0 * x0) : (x1 - x0));
      const double limit = settings_.support_threshold * own;
      if (support[std::size_t(n)] < limit)
        weakness[std::size_t(n)] = 1.0 - support[std::size_t(n)] / limit;
      if (reached_by[std::size_t(n)] < fewest)
        weakness[std::size_t(n)] =
            std::max(weakness[std::size_t(n)], 1.0 - double(reached_by[std::size_t(n)]) / fewest);
      // A node inside a rigid body has only the tails of the shape functions of the soil beside
      // the body, yet the contact forces of that soil's domain corners reach it: it is weak.
      if (settings_.inside_body_weakness > 0.0) {
        const Vec2 at(grid_.x_axis().node(i), grid_.y_axis().node(j));
        for (const RigidBody& body : bodies_)
          if (body.signed_distance(at) < -1.0e-9 * grid_.min_spacing())
            weakness[std::size_t(n)] =
                std::max(weakness[std::size_t(n)], settings_.inside_body_weakness);
      }
      setup.active[std::size_t(n)] = 1;
      if (free_x[std::size_t(n)] != 0.0) setup.dof[2 * std::size_t(n)] = setup.unknowns++;
      if (free_y[std::size_t(n)] != 0.0) setup.dof[2 * std::size_t(n) + 1] = setup.unknowns++;
    }
  if (settings_.ghost_stiffness > 0.0)
    for (int j = 0; j < grid_.ny(); ++j)
      for (int i = 0; i < nx; ++i) {
        const int n = grid_.node_index(i, j);
        if (!(weakness[std::size_t(n)] > 0.0)) continue;
        const double scale =
            axisymmetric ? std::max(grid_.x_axis().node(i), 0.5 * grid_.x_axis().spacing(0)) : 1.0;
        const double k =
            settings_.ghost_stiffness * modulus[std::size_t(n)] * weakness[std::size_t(n)] * scale;
        const int neighbours[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
        for (const auto& ij : neighbours) {
          if (ij[0] < 0 || ij[0] >= nx || ij[1] < 0 || ij[1] >= grid_.ny()) continue;
          const int m = grid_.node_index(ij[0], ij[1]);
          // Towards better support, and once between equally weak neighbours (a group of
          // nodes that one particle alone reaches is tied together as well as to the rest).
          const double theirs = weakness[std::size_t(m)], mine = weakness[std::size_t(n)];
          if (!setup.active[std::size_t(m)] || theirs > mine || (theirs == mine && m < n)) continue;
          setup.ghosts.push_back({n, m, k});
        }
      }
  setup.cells.clear();
  setup.cell.assign(count, -1);
  setup.slot.assign(settings_.volumetric_averaging ? count : 0, {});
  if (settings_.volumetric_averaging) {
    const int cells_x = grid_.x_axis().cell_count();
    std::vector<int> index(std::size_t(cells_x * grid_.y_axis().cell_count()), -1);
    std::vector<double> cell_volume;
    for (std::size_t i = 0; i < count; ++i) {
      const int c = grid_.y_axis().cell_of(p.position[i].y()) * cells_x +
                    grid_.x_axis().cell_of(p.position[i].x());
      if (index[std::size_t(c)] < 0) {
        index[std::size_t(c)] = static_cast<int>(setup.cells.size());
        setup.cells.emplace_back();
        cell_volume.push_back(0.0);
      }
      const int k_cell = index[std::size_t(c)];
      setup.cell[i] = k_cell;
      StepSetup::CellMean& mean = setup.cells[std::size_t(k_cell)];
      cell_volume[std::size_t(k_cell)] += p.volume[i];
      const ParticleNodes& pn = setup.nodes[i];
      for (int k = 0; k < pn.count; ++k) {
        int j = 0;
        while (j < mean.count && mean.node[j] != pn.node[k]) ++j;
        if (j == mean.count) {
          if (mean.count == kMaxCellNodes)
            throw Error(
                fmt::format("quasi-static: the particles of a cell reach more than {} "
                            "nodes (particle {})",
                            kMaxCellNodes, i));
          mean.node[j] = pn.node[k];
          mean.row[j] = Vec2::Zero();
          ++mean.count;
        }
        setup.slot[i][std::size_t(k)] = j;
        const double hoop = axisymmetric ? pn.weight[k] / p.position[i].x() : 0.0;
        mean.row[j] += p.volume[i] * Vec2(pn.gradient[k].x() + hoop, pn.gradient[k].y());
      }
    }
    for (std::size_t c = 0; c < setup.cells.size(); ++c)
      for (int j = 0; j < setup.cells[c].count; ++j) setup.cells[c].row[j] /= cell_volume[c];
  }
  build_pattern(setup);
  setup.surfaces.clear();
  for (const RigidBody& body : bodies_)
    setup.surfaces.emplace_back(body, settings_.contact.vertex_radius * grid_.min_spacing());
  setup.near_body.assign(count, 0);
  if (!bodies_.empty())
    for (std::size_t i = 0; i < count; ++i) {
      const double reach = p.half_size[i].norm() + 2.0 * grid_.min_spacing();
      for (const RigidBody& body : bodies_)
        if (body.signed_distance(p.position[i]) < reach) setup.near_body[i] = 1;
    }
}

void QuasiStaticSolver::build_pattern(StepSetup& setup) const {
  const bool averaging = settings_.volumetric_averaging;
  const int blocks = static_cast<int>(averaging ? setup.cells.size() : setup.nodes.size());
  setup.block.resize(setup.nodes.size());
  for (std::size_t i = 0; i < setup.nodes.size(); ++i)
    setup.block[i] = averaging ? setup.cell[i] : static_cast<int>(i);
  setup.scatter_offset.assign(std::size_t(blocks) + 1, 0);
  for (int b = 0; b < blocks; ++b) {
    int width = 0;
    setup.block_nodes(b, width);
    setup.scatter_offset[std::size_t(b) + 1] =
        setup.scatter_offset[std::size_t(b)] + std::size_t(4 * width * width);
  }
  // The pattern: per column the rows it meets, sorted and unique.
  std::vector<std::vector<int>> rows(std::size_t(setup.unknowns));
  for (int b = 0; b < blocks; ++b) {
    int width = 0;
    const int* node = setup.block_nodes(b, width);
    for (int c = 0; c < 2 * width; ++c) {
      const int column = setup.dof[2 * std::size_t(node[c / 2]) + std::size_t(c % 2)];
      if (column < 0) continue;
      for (int r = 0; r < 2 * width; ++r) {
        const int row = setup.dof[2 * std::size_t(node[r / 2]) + std::size_t(r % 2)];
        if (row >= 0) rows[std::size_t(column)].push_back(row);
      }
    }
  }
  for (const StepSetup::GhostSpring& ghost : setup.ghosts)
    for (int c = 0; c < 2; ++c) {
      const int a = setup.dof[2 * std::size_t(ghost.node_a) + std::size_t(c)];
      const int b = setup.dof[2 * std::size_t(ghost.node_b) + std::size_t(c)];
      if (a >= 0) rows[std::size_t(a)].push_back(a);
      if (b >= 0) rows[std::size_t(b)].push_back(b);
      if (a >= 0 && b >= 0) {
        rows[std::size_t(a)].push_back(b);
        rows[std::size_t(b)].push_back(a);
      }
    }
  std::size_t entries = 0;
  for (std::vector<int>& column : rows) {
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    entries += column.size();
  }
  SparseMatrix& pattern = setup.pattern;
  pattern.resize(setup.unknowns, setup.unknowns);
  pattern.resizeNonZeros(static_cast<Eigen::Index>(entries));
  int* outer = pattern.outerIndexPtr();
  int* inner = pattern.innerIndexPtr();
  outer[0] = 0;
  for (int c = 0; c < setup.unknowns; ++c) {
    const std::vector<int>& column = rows[std::size_t(c)];
    std::copy(column.begin(), column.end(), inner + outer[c]);
    outer[c + 1] = outer[c] + static_cast<int>(column.size());
  }
  std::fill(pattern.valuePtr(), pattern.valuePtr() + entries, 0.0);
  // The entry of (row, column) in the pattern.
  const auto entry = [&](int row, int column) {
    if (row < 0 || column < 0) return -1;
    const int* begin = inner + outer[column];
    const int* end = inner + outer[column + 1];
    const int* at = std::lower_bound(begin, end, row);
    return at != end && *at == row ? static_cast<int>(at - inner) : -1;
  };
  setup.scatter.assign(setup.scatter_offset.back(), -1);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads_)
  for (int b = 0; b < blocks; ++b) {
    int width = 0;
    const int* node = setup.block_nodes(b, width);
    int* map = setup.scatter.data() + setup.scatter_offset[std::size_t(b)];
    for (int c = 0; c < 2 * width; ++c) {
      const int column = setup.dof[2 * std::size_t(node[c / 2]) + std::size_t(c % 2)];
      for (int r = 0; r < 2 * width; ++r)
        map[c * 2 * width + r] =
            entry(setup.dof[2 * std::size_t(node[r / 2]) + std::size_t(r % 2)], column);
    }
  }
  setup.ghost_entry.clear();
  for (const StepSetup::GhostSpring& ghost : setup.ghosts)
    for (int c = 0; c < 2; ++c) {
      const int a = setup.dof[2 * std::size_t(ghost.node_a) + std::size_t(c)];
      const int b = setup.dof[2 * std::size_t(ghost.node_b) + std::size_t(c)];
      setup.ghost_entry.push_back({entry(a, a), entry(b, b), entry(a, b), entry(b, a)});
    }
}

}  // namespace pilempm::mpm::quasi_static
