// The quasi-static solver's per-iterate work: the set-up of a sub-increment (stencils, unknowns,
// ghost springs, volumetric averaging) and the evaluation of an iterate (strains, stresses and
// tangents, internal, external and contact forces, the residual and the Newton matrix).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"
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
  for (std::size_t i = 0; i < count; ++i) {
    Stencil stencil;
    compute_stencil(grid_, settings_.shape_function, p.position[i].x(), p.position[i].y(),
                    p.half_size[i].x(), p.half_size[i].y(), stencil);
    flatten(stencil, nx, setup.nodes[i]);
    const ParticleNodes& pn = setup.nodes[i];
    for (int k = 0; k < pn.count; ++k)
      support[std::size_t(pn.node[k])] += pn.weight[k] * p.volume[i];
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
  std::vector<double> weakness(std::size_t(nodes), 0.0);  // 1 - s_i / (threshold v_i), or 0
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
          if (!setup.active[std::size_t(m)] || weakness[std::size_t(m)] >= weakness[std::size_t(n)])
            continue;
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

bool QuasiStaticSolver::evaluate(const StepSetup& setup, const std::vector<double>& du,
                                 double gravity, double traction,
                                 const std::vector<Vec2>& body_step, bool tangent, Trial& trial,
                                 LoadStepResult& result) const {
  const Particles& p = particles_;
  const long count = static_cast<long>(p.size());
  const int nodes = grid_.node_count();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const bool first_matrix =
      tangent && std::all_of(du.begin(), du.end(), [](double v) { return v == 0.0; });
  const auto material_start = std::chrono::steady_clock::now();

  trial.node_displacement.assign(std::size_t(nodes), Vec2::Zero());
  for (int n = 0; n < nodes; ++n)
    for (int c = 0; c < 2; ++c) {
      const int d = setup.dof[2 * std::size_t(n) + std::size_t(c)];
      if (d >= 0) trial.node_displacement[std::size_t(n)][c] = du[std::size_t(d)];
    }
  trial.state.resize(std::size_t(count));
  trial.strain_increment.resize(std::size_t(count));
  trial.gradient.resize(std::size_t(count));
  trial.hoop.resize(std::size_t(count));
  if (tangent) trial.tangent.resize(std::size_t(count));

  // Kinematics, the stress from the converged state and the tangent, particle by particle.
  bool failed = false;
  int floor_particles = 0;
  const TangentKind kind = settings_.tangent;
  // The strain components that vary (rows of B): plane strain has no 33.
  const int used_columns = axisymmetric ? 4 : 3;
  const int used_column[4] = {0, 1, axisymmetric ? 2 : 3, 3};
  const bool averaging = settings_.volumetric_averaging;
  const double normal_components = axisymmetric ? 3.0 : 2.0;
#pragma omp parallel for schedule(static) num_threads(threads_) reduction(|| : failed) \
    reduction(+ : floor_particles)
  for (long i = 0; i < count; ++i) {
    const ParticleNodes& pn = setup.nodes[std::size_t(i)];
    Mat2 gradient = Mat2::Zero();
    double radial = 0.0;
    for (int k = 0; k < pn.count; ++k) {
      const Vec2& u = trial.node_displacement[std::size_t(pn.node[k])];
      gradient += u * pn.gradient[k].transpose();
      radial += pn.weight[k] * u.x();
    }
    const double hoop = axisymmetric ? radial / p.position[std::size_t(i)].x() : 0.0;
    Vec6 strain;
    strain << gradient(0, 0), gradient(1, 1), hoop, 0.0, 0.0,
        kSqrt2 * 0.5 * (gradient(0, 1) + gradient(1, 0));
    if (averaging) {  // the cell's mean volumetric increment replaces the particle's own
      const StepSetup::CellMean& mean = setup.cells[std::size_t(setup.cell[std::size_t(i)])];
      double mean_volumetric = 0.0;
      for (int j = 0; j < mean.count; ++j)
        mean_volumetric += mean.row[j].dot(trial.node_displacement[std::size_t(mean.node[j])]);
      const double correction =
          (mean_volumetric - (strain[k11] + strain[k22] + strain[k33])) / normal_components;
      strain[k11] += correction;
      strain[k22] += correction;
      if (axisymmetric) strain[k33] += correction;
    }
    trial.gradient[std::size_t(i)] = gradient;
    trial.hoop[std::size_t(i)] = hoop;
    trial.strain_increment[std::size_t(i)] = strain;
    // Hughes-Winget: rotate the converged state by the spin, then integrate the increment.
    MaterialState rotated = p.state[std::size_t(i)];
    const double spin = 0.5 * (gradient(1, 0) - gradient(0, 1));
    const ConstitutiveModel& model = *materials_[std::size_t(p.material[std::size_t(i)])];
    if (spin != 0.0) rotate_state_about_z(rotated, spin, model.history_variables());
    MaterialState& state = trial.state[std::size_t(i)];
    state = rotated;
    const UpdateResult update = model.update(state, strain);
    if (!update.ok) {
      failed = true;
      continue;
    }
    if (update.mean_stress_floor_hits > 0) ++floor_particles;
    if (!tangent) continue;
    Mat4& d = trial.tangent[std::size_t(i)];
    d.setZero();
    // On the stress floor the integrated update does not change with the strain (a zero
    // derivative would leave the nodes such particles alone support without stiffness): a small
    // isotropic elastic stiffness instead (Settings::floor_stiffness), in the matrix only.
    const auto elastic_fallback = [&] {
      // E from the constrained modulus M = E (1 − ν) / ((1 + ν)(1 − 2ν)).
      const double m = settings_.floor_stiffness * model.wave_modulus(p.state[std::size_t(i)]);
      const double nu = kFallbackPoisson;
      d = in_plane(
          ElasticParameters{m * (1.0 + nu) * (1.0 - 2.0 * nu) / (1.0 - nu), nu}.stiffness());
    };
    if (update.mean_stress_floor_hits > 0) {
      elastic_fallback();
      continue;
    }
    const bool analytic =
        kind == TangentKind::elastic ||
        (kind == TangentKind::automatic && dynamic_cast<const LinearElastic*>(&model) != nullptr);
    if (analytic) {
      d = in_plane(model.tangent(state, strain));
      continue;
    }
    // Fellin & Ostermann (2002): forward differences of the integrated update.
    const double h = settings_.perturbation * std::max(strain.norm(), 1.0e-6);
    for (int c = 0; c < used_columns; ++c) {
      const int dc = used_column[c];
      Vec6 perturbed = strain;
      perturbed[kComponents[dc]] += h;
      MaterialState probe = rotated;
      if (!model.update(probe, perturbed).ok) {  // a probe beyond the model's domain
        elastic_fallback();
        break;
      }
      const Vec6 difference = (probe.stress - state.stress) / h;
      for (int r = 0; r < 4; ++r) d(r, dc) = difference[kComponents[r]];
    }
  }
  result.seconds_material += seconds_since(material_start);
  trial.floor_particles = floor_particles;
  if (failed) return false;

  // Assembly: internal and external forces, the material stiffness.
  const auto assembly_start = std::chrono::steady_clock::now();
  trial.internal.assign(2 * std::size_t(nodes), 0.0);
  trial.external.assign(2 * std::size_t(nodes), 0.0);
  trial.contact.assign(2 * std::size_t(nodes), 0.0);
  if (tangent) trial.triplets.clear();
  const double body_force = -gravity * settings_.gravity;
  // B (4 rows, 2 columns per node) over the particle's nodes, or with volumetric averaging
  // B̄ = B + m (b̄ − b_p)^T / n over the nodes of its cell (m: ones in the normal rows, b_p the
  // particle's volumetric row, b̄ the cell's mean, n = 2 in plane strain, 3 in axisymmetry).
  Eigen::Matrix<double, 4, 2 * kMaxCellNodes> b;
  for (long i = 0; i < count; ++i) {
    const ParticleNodes& pn = setup.nodes[std::size_t(i)];
    const double volume = p.volume[std::size_t(i)];
    const Vec6& s = trial.state[std::size_t(i)].stress;
    const double radius = p.position[std::size_t(i)].x();
    const Vec2 load = traction * p.external_force[std::size_t(i)] +
                      Vec2(0.0, p.mass[std::size_t(i)] * body_force);
    const StepSetup::CellMean* mean =
        averaging ? &setup.cells[std::size_t(setup.cell[std::size_t(i)])] : nullptr;
    const int width = mean != nullptr ? mean->count : pn.count;
    const int* column_node = mean != nullptr ? mean->node : pn.node;
    b.leftCols(2 * width).setZero();
    for (int k = 0; k < pn.count; ++k) {
      const int j = mean != nullptr ? setup.slot[std::size_t(i)][std::size_t(k)] : k;
      const Vec2& g = pn.gradient[k];
      b(0, 2 * j) = g.x();
      b(1, 2 * j + 1) = g.y();
      if (axisymmetric) b(2, 2 * j) = pn.weight[k] / radius;
      b(3, 2 * j) = g.y() / kSqrt2;
      b(3, 2 * j + 1) = g.x() / kSqrt2;
    }
    if (mean != nullptr)
      for (int j = 0; j < width; ++j)
        for (int c = 0; c < 2; ++c) {
          const double own = b(0, 2 * j + c) + b(1, 2 * j + c) + b(2, 2 * j + c);
          const double correction = (mean->row[j][c] - own) / normal_components;
          b(0, 2 * j + c) += correction;
          b(1, 2 * j + c) += correction;
          if (axisymmetric) b(2, 2 * j + c) += correction;
        }
    const Vec4 stress4(s[k11], s[k22], s[k33], s[k12]);
    for (int j = 0; j < width; ++j) {
      const std::size_t n = std::size_t(column_node[j]);
      trial.internal[2 * n] += volume * b.col(2 * j).dot(stress4);
      trial.internal[2 * n + 1] += volume * b.col(2 * j + 1).dot(stress4);
    }
    for (int k = 0; k < pn.count; ++k) {
      const std::size_t n = std::size_t(pn.node[k]);
      trial.external[2 * n] += pn.weight[k] * load.x();
      trial.external[2 * n + 1] += pn.weight[k] * load.y();
    }
    if (!tangent) continue;
    const int columns = 2 * width;
    const Eigen::Matrix<double, 4, Eigen::Dynamic> db =
        volume * trial.tangent[std::size_t(i)] * b.leftCols(columns);
    for (int c = 0; c < columns; ++c) {
      const int col = setup.dof[2 * std::size_t(column_node[c / 2]) + std::size_t(c % 2)];
      if (col < 0) continue;
      for (int r = 0; r < columns; ++r) {
        const int row = setup.dof[2 * std::size_t(column_node[r / 2]) + std::size_t(r % 2)];
        if (row < 0) continue;
        trial.triplets.emplace_back(row, col, b.col(r).dot(db.col(c)));
      }
    }
  }

  // Contact at the corners of the particles' domains against the bodies' exact surfaces.
  trial.contact_triplets = trial.triplets.size();
  trial.corner.assign(std::size_t(count) * kCorners, PointContact{});
  trial.corner_body.assign(std::size_t(count) * kCorners, -1);
  trial.corner_part.assign(std::size_t(count) * kCorners, 0);
  trial.corner_gap.assign(std::size_t(count) * kCorners, 0.0);
  for (long i = 0; i < count && !bodies_.empty(); ++i) {
    if (!setup.near_body[std::size_t(i)]) continue;
    const ParticleNodes& pn = setup.nodes[std::size_t(i)];
    const Vec2& x = p.position[std::size_t(i)];
    const Vec2& l = p.half_size[std::size_t(i)];
    const double modulus = contact_modulus_[std::size_t(p.material[std::size_t(i)])];
    const double size = 2.0 * std::min(l.x(), l.y());
    for (int q = 0; q < kCorners; ++q) {
      // The corners are contact points that move with the particle's affine motion (material
      // points of their own, so that a converged gap carries over to the next step unchanged):
      // Δu_q = Σ_k c_k Δu_k, c_k = S_k + ∇S_k · (x_q - x_p).
      const Vec2 corner = corner_position_[std::size_t(i) * kCorners + std::size_t(q)];
      const Vec2 offset = corner - x;
      double coefficient[16];
      Vec2 moved = Vec2::Zero();
      for (int k = 0; k < pn.count; ++k) {
        coefficient[k] = pn.weight[k] + pn.gradient[k].dot(offset);
        moved += coefficient[k] * trial.node_displacement[std::size_t(pn.node[k])];
      }
      const double area = (l.x() + l.y()) * (axisymmetric ? std::abs(corner.x()) : 1.0);
      const double normal_stiffness = settings_.contact.penalty_factor * modulus * area / size;
      // Points this close outside keep the stick stiffness in the matrix (see penalty_contact).
      // Only in the first matrix of an increment: later on it would be a spring without force.
      const double margin = first_matrix ? settings_.contact.stiffness_margin * size : 0.0;
      const std::size_t index = std::size_t(i) * kCorners + std::size_t(q);
      (void)l;
      for (std::size_t body = 0; body < bodies_.size(); ++body) {
        const Vec2 body_move = body < body_step.size() ? body_step[body] : Vec2::Zero();
        const SurfaceQuery hit = setup.surfaces[body].query(corner + moved - body_move);
        if (!(hit.distance < margin)) continue;
        const ContactHistory& history = contact_history_[index];
        const Vec2 previous =
            history.body == static_cast<int>(body) ? history.tangential_force : Vec2::Zero();
        const PointContact point =
            penalty_contact(hit.distance, hit.normal, moved - body_move, previous, normal_stiffness,
                            settings_.contact.tangential_ratio * normal_stiffness,
                            bodies_[body].friction(), margin, settings_.contact.smoothing * size);
        if (point.active) {
          trial.corner[index] = point;
          trial.corner_body[index] = static_cast<int>(body);
          trial.corner_part[index] = hit.part;
          trial.corner_gap[index] = hit.distance;
          for (int k = 0; k < pn.count; ++k) {
            const std::size_t n = std::size_t(pn.node[k]);
            trial.contact[2 * n] += coefficient[k] * point.force.x();
            trial.contact[2 * n + 1] += coefficient[k] * point.force.y();
          }
        }
        if (tangent)
          for (int a = 0; a < pn.count; ++a)
            for (int c = 0; c < pn.count; ++c) {
              const Mat2 block = coefficient[a] * coefficient[c] * point.stiffness;
              for (int r = 0; r < 2; ++r)
                for (int s = 0; s < 2; ++s) {
                  const int row = setup.dof[2 * std::size_t(pn.node[a]) + std::size_t(r)];
                  const int col = setup.dof[2 * std::size_t(pn.node[c]) + std::size_t(s)];
                  if (row >= 0 && col >= 0) trial.triplets.emplace_back(row, col, block(r, s));
                }
            }
        break;  // one body per corner
      }
    }
  }

  // Ghost springs between weakly supported nodes and their neighbours (internal forces).
  trial.ghost_triplets = trial.triplets.size();
  for (const StepSetup::GhostSpring& ghost : setup.ghosts) {
    const Vec2 stretch = trial.node_displacement[std::size_t(ghost.node_a)] -
                         trial.node_displacement[std::size_t(ghost.node_b)];
    for (int c = 0; c < 2; ++c) {
      const std::size_t ca = 2 * std::size_t(ghost.node_a) + std::size_t(c);
      const std::size_t cb = 2 * std::size_t(ghost.node_b) + std::size_t(c);
      trial.internal[ca] += ghost.stiffness * stretch[c];
      trial.internal[cb] -= ghost.stiffness * stretch[c];
      if (!tangent) continue;
      const int da = setup.dof[ca], db = setup.dof[cb];
      if (da >= 0) trial.triplets.emplace_back(da, da, ghost.stiffness);
      if (db >= 0) trial.triplets.emplace_back(db, db, ghost.stiffness);
      if (da >= 0 && db >= 0) {
        trial.triplets.emplace_back(da, db, -ghost.stiffness);
        trial.triplets.emplace_back(db, da, -ghost.stiffness);
      }
    }
  }
  trial.residual.setZero(setup.unknowns);
  double internal_norm = 0.0, external_norm = 0.0, contact_norm = 0.0;
  for (std::size_t c = 0; c < 2 * std::size_t(nodes); ++c) {
    if (!setup.active[c / 2]) continue;
    internal_norm += trial.internal[c] * trial.internal[c];
    external_norm += trial.external[c] * trial.external[c];
    contact_norm += trial.contact[c] * trial.contact[c];
    const int d = setup.dof[c];
    if (d >= 0) trial.residual[d] = trial.internal[c] - trial.external[c] - trial.contact[c];
  }
  trial.reference_force = std::sqrt(std::max({internal_norm, external_norm, contact_norm}));
  result.seconds_assembly += seconds_since(assembly_start);
  return trial.residual.allFinite();
}

}  // namespace pilempm::mpm::quasi_static
