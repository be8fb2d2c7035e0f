#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/in_plane_rotation.hpp"

namespace pilempm::mpm::quasi_static {

namespace {

// The Mandel components an in-plane problem uses, in the order of the 4-row B matrices.
constexpr int kComponents[4] = {k11, k22, k33, k12};
constexpr int kCorners = 4;
// Poisson's ratio of the elastic stiffness that stands in for the tangent of a particle on the
// model's stress floor (or whose perturbation leaves the model's domain).
constexpr double kFallbackPoisson = 0.3;
// The most nodes the particles of one cell reach together (volumetric averaging).
constexpr int kMaxCellNodes = 36;
using Mat4 = Eigen::Matrix4d;
using Vec4 = Eigen::Vector4d;

// The rows and columns 11, 22, 33, 12 of a Mandel stiffness.
Mat4 in_plane(const Mat6& full) {
  Mat4 d;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) d(r, c) = full(kComponents[r], kComponents[c]);
  return d;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The weights of a particle's stencil as a flat list of nodes (row-major over the stencil).
struct ParticleNodes {
  int count = 0;
  int node[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
  double weight[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
  Vec2 gradient[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
};

void flatten(const Stencil& stencil, int nx, ParticleNodes& out) {
  out.count = 0;
  for (int b = 0; b < stencil.y.count; ++b)
    for (int a = 0; a < stencil.x.count; ++a) {
      const int k = out.count++;
      out.node[k] = (stencil.y.first + b) * nx + stencil.x.first + a;
      out.weight[k] = stencil.x.weight[a] * stencil.y.weight[b];
      out.gradient[k] = Vec2(stencil.x.gradient[a] * stencil.y.weight[b],
                             stencil.x.weight[a] * stencil.y.gradient[b]);
    }
}

// Length of node i's share of an axis (half of each adjacent cell) as the interval [lo, hi].
void node_share(const GridAxis& axis, int i, double& lo, double& hi) {
  lo = i > 0 ? 0.5 * (axis.node(i - 1) + axis.node(i)) : axis.node(i);
  hi = i + 1 < axis.node_count() ? 0.5 * (axis.node(i) + axis.node(i + 1)) : axis.node(i);
}

// A rigid body's surface with its vertices rounded by a radius ρ: the points within ρ of the
// inner polygon Q, whose edges are the body's edges moved inward by ρ. The gap is d_Q − ρ, d_Q
// the signed distance to Q, and the normal that of d_Q. On the faces this is the body's own
// surface; at a vertex the normal turns continuously over an arc of radius ρ, also for points
// that have penetrated (up to ρ). The sharp polygon's normal inside the body jumps at the
// bisector of each vertex (by 30° at the pile's shoulder, 90° at a footing's edge), so that a
// penetrated contact point passing a vertex changes its force's direction at once and the Newton
// iterations chatter (docs/quasi-static.md).
struct RoundedSurface {
  RigidBody inner;        // Q, a polygon (for a pile: its mirrored section, queried at |r|)
  std::vector<int> part;  // the body's surface part of Q's edge k
  double radius = 0.0;
  bool axisymmetric = false;

  RoundedSurface(const RigidBody& body, double rounding)
      : inner(RigidBody::polygon(inner_vertices(body, rounding))),
        radius(rounding),
        axisymmetric(body.axisymmetric()) {
    const std::vector<Vec2>& v = body.vertices();
    for (std::size_t k = 0; k < v.size(); ++k) {
      // The part of the edge, as the body reports it just outside the edge's middle.
      const Vec2 edge = v[(k + 1) % v.size()] - v[k];
      const Vec2 normal = Vec2(edge.y(), -edge.x()).normalized();
      part.push_back(body.query(v[k] + 0.5 * edge + 1.0e-9 * edge.norm() * normal).part);
    }
  }

  // Vertex k joins edges k − 1 and k; moved inward along the mitre it lies ρ from both lines.
  static std::vector<Vec2> inner_vertices(const RigidBody& body, double rounding) {
    const std::vector<Vec2>& v = body.vertices();
    const std::size_t count = v.size();
    auto normal = [&](std::size_t k) {
      const Vec2 edge = v[(k + 1) % count] - v[k];
      return Vec2(Vec2(edge.y(), -edge.x()).normalized());
    };
    std::vector<Vec2> q;
    for (std::size_t k = 0; k < count; ++k) {
      const Vec2 a = normal((k + count - 1) % count), b = normal(k);
      q.push_back(v[k] - rounding * (a + b) / (1.0 + a.dot(b)));
    }
    return q;
  }

  SurfaceQuery query(const Vec2& point) const {
    SurfaceQuery result = inner.query(axisymmetric ? Vec2(std::abs(point.x()), point.y()) : point);
    result.distance -= radius;
    result.part = part[std::size_t(result.part)];
    if (axisymmetric && point.x() < 0.0) result.normal.x() = -result.normal.x();
    return result;
  }
};

}  // namespace

void Settings::validate() const {
  auto positive = [](double value, const char* key) {
    if (!(value > 0.0) || !std::isfinite(value))
      throw InvalidValue(key, format_value(value), "> 0");
  };
  if (!(gravity >= 0.0) || !std::isfinite(gravity))
    throw InvalidValue("gravity", format_value(gravity), ">= 0");
  positive(force_tolerance, "force_tolerance");
  positive(energy_tolerance, "energy_tolerance");
  positive(perturbation, "perturbation");
  positive(floor_stiffness, "floor_stiffness");
  if (max_iterations < 1)
    throw InvalidValue("max_iterations", std::to_string(max_iterations), ">= 1");
  if (line_search_steps < 0)
    throw InvalidValue("line_search_steps", std::to_string(line_search_steps), ">= 0");
  if (!(step_limit >= 0.0) || !std::isfinite(step_limit))
    throw InvalidValue("step_limit", format_value(step_limit), ">= 0");
  if (max_cuts < 0) throw InvalidValue("max_cuts", std::to_string(max_cuts), ">= 0");
  if (easy_iterations < 0)
    throw InvalidValue("easy_iterations", std::to_string(easy_iterations), ">= 0");
  if (!(support_threshold >= 0.0 && support_threshold < 1.0))
    throw InvalidValue("support_threshold", format_value(support_threshold), "in [0, 1)");
  if (!(ghost_stiffness >= 0.0) || !std::isfinite(ghost_stiffness))
    throw InvalidValue("ghost_stiffness", format_value(ghost_stiffness), ">= 0");
  if (threads < 0) throw InvalidValue("threads", std::to_string(threads), ">= 0");
  if (linear_solver == LinearSolverKind::umfpack && !umfpack_available())
    throw InvalidValue("linear_solver", "umfpack", "sparse-lu (this build has no UMFPACK)");
  contact.validate();
}

// What the iterations of one sub-increment share: the reference configuration's stencils and
// the unknowns.
struct QuasiStaticSolver::StepSetup {
  std::vector<ParticleNodes> nodes;  // per particle
  std::vector<int> dof;              // per node component (2 per node): unknown index or -1
  std::vector<char> active;          // per node
  int unknowns = 0;
  std::vector<char> near_body;  // per particle: whether its corners are checked for contact
  struct GhostSpring {
    int node_a, node_b;
    double stiffness;
  };
  std::vector<GhostSpring> ghosts;
  std::vector<RoundedSurface> surfaces;  // per body, at its start-of-increment position
  // Volumetric averaging (Settings::volumetric_averaging): per cell, the nodes its particles
  // reach and the volume-weighted mean volumetric row b̄ (x, y per node); per particle its cell
  // and where each of its nodes sits in the cell's list.
  struct CellMean {
    int count = 0;
    int node[kMaxCellNodes];
    Vec2 row[kMaxCellNodes];
  };
  std::vector<CellMean> cells;
  std::vector<int> cell;                  // per particle
  std::vector<std::array<int, 16>> slot;  // per particle and stencil node
};

// The results of evaluating one iterate.
struct QuasiStaticSolver::Trial {
  std::vector<MaterialState> state;
  std::vector<Vec6> strain_increment;
  std::vector<Mat2> gradient;  // G = Σ Δu_i ⊗ ∇S_i
  std::vector<double> hoop;
  std::vector<Mat4> tangent;
  std::vector<Vec2> node_displacement;              // per node
  std::vector<double> internal, external, contact;  // per node component
  std::vector<PointContact> corner;                 // per particle corner
  std::vector<int> corner_body, corner_part;        // per particle corner
  std::vector<double> corner_gap;                   // per particle corner
  Eigen::VectorXd residual;                         // per unknown
  std::vector<Eigen::Triplet<double>> triplets;
  double reference_force = 0.0;
  int floor_particles = 0;  // stress updates that ended on the model's mean stress floor
};

QuasiStaticSolver::QuasiStaticSolver(Grid grid, Particles particles,
                                     std::vector<ModelPtr> materials, Settings settings)
    : grid_(std::move(grid)),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      settings_(settings) {
  settings_.validate();
  linear_solver_.set_kind(settings_.linear_solver);
  threads_ = settings_.threads > 0 ? settings_.threads : omp_get_max_threads();
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (axisymmetric && grid_.x_axis().start() < 0.0)
    throw InvalidValue("grid x start", format_value(grid_.x_axis().start()), ">= 0 in axisymmetry");
  if (axisymmetric && grid_.x_axis().start() == 0.0) grid_.set_axis_of_symmetry(true);
  for (std::size_t p = 0; p < particles_.size(); ++p) {
    const auto what = [&](const char* field) { return fmt::format("particle {} {}", p, field); };
    const int material = particles_.material[p];
    if (material < 0 || material >= static_cast<int>(materials_.size()) ||
        !materials_[std::size_t(material)])
      throw InvalidValue(what("material"), std::to_string(material),
                         fmt::format("a model index in [0, {})", materials_.size()));
    if (!(particles_.volume[p] > 0.0))
      throw InvalidValue(what("volume"), format_value(particles_.volume[p]), "> 0");
    const Vec2& x = particles_.position[p];
    if (!grid_.contains(x.x(), x.y()))
      throw InvalidValue(what("position"), fmt::format("({}, {})", x.x(), x.y()),
                         "inside the grid");
    if (axisymmetric && !(x.x() > 0.0))
      throw InvalidValue(what("radius"), format_value(x.x()), "> 0 in axisymmetry");
  }
  contact_history_.assign(particles_.size() * kCorners, ContactHistory{});
  corner_position_.resize(particles_.size() * kCorners);
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Vec2& l = particles_.half_size[i];
    for (int q = 0; q < kCorners; ++q)
      corner_position_[i * kCorners + std::size_t(q)] =
          particles_.position[i] + Vec2((q & 1) ? l.x() : -l.x(), (q & 2) ? l.y() : -l.y());
  }
  node_displacement_.assign(std::size_t(grid_.node_count()), Vec2::Zero());
  contact_modulus_.assign(materials_.size(), 0.0);
}

int QuasiStaticSolver::add_rigid_body(RigidBody body) {
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (body.axisymmetric() != axisymmetric)
    throw InvalidValue("rigid body", body.axisymmetric() ? "pile" : "polygon",
                       axisymmetric ? "a pile in axisymmetry" : "a polygon in plane strain");
  // A body put where particles are (a pile wished in place) has the corners of the particles
  // next to it inside it, up to half a particle deep: their penalty forces would be of the order
  // of the modulus instead of the stress. Such contact points start on the surface instead, free
  // of strain and force (as an initial overclosure is adjusted in finite element contact).
  for (Vec2& corner : corner_position_) {
    const SurfaceQuery hit = body.query(corner);
    if (hit.distance < 0.0) corner -= hit.distance * hit.normal;
  }
  BodyForce force;
  force.parts.assign(std::size_t(body.part_count()), Vec2::Zero());
  bodies_.push_back(std::move(body));
  body_forces_.push_back(std::move(force));
  return rigid_body_count() - 1;
}

void QuasiStaticSolver::set_material(int index, ModelPtr model) {
  if (index < 0 || index >= static_cast<int>(materials_.size()) || !model)
    throw InvalidValue("material index", std::to_string(index),
                       fmt::format("[0, {}) and a model", materials_.size()));
  materials_[std::size_t(index)] = std::move(model);
}

void QuasiStaticSolver::fix_contact_modulus() {
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const std::size_t m = std::size_t(particles_.material[i]);
    contact_modulus_[m] =
        std::max(contact_modulus_[m], materials_[m]->wave_modulus(particles_.state[i]));
  }
}

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
                            bodies_[body].friction(), margin);
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

bool QuasiStaticSolver::solve_sub_increment(double fraction, const LoadStep& load,
                                            SubIncrementRecord& record, LoadStepResult& result) {
  // The sub-increment's targets, linear in the fraction of the step from the current state.
  const double gravity =
      gravity_multiplier_ + fraction * (load.gravity_multiplier - gravity_multiplier_);
  const double traction =
      traction_multiplier_ + fraction * (load.traction_multiplier - traction_multiplier_);
  std::vector<Vec2> body_step(bodies_.size(), Vec2::Zero());
  for (std::size_t b = 0; b < bodies_.size() && b < load.body_displacement.size(); ++b)
    body_step[b] = fraction * load.body_displacement[b];

  StepSetup setup;
  build_setup(setup);
  result.unknowns = setup.unknowns;
  std::vector<double> du(std::size_t(setup.unknowns), 0.0);
  Trial trial;
  if (!evaluate(setup, du, gravity, traction, body_step, true, trial, result)) {
    result.message = "a stress update failed at the start of the increment";
    return false;
  }
  // Predictor: the last increment's nodal displacements scaled to this one's body motion, kept
  // when it lowers the residual (a pile pushed on deforms the soil much as in the last step).
  double body_motion = 0.0;
  for (const Vec2& d : body_step) body_motion = std::max(body_motion, d.norm());
  if (settings_.predictor && body_motion > 0.0 && last_body_step_ > 0.0) {
    const double scale = body_motion / last_body_step_;
    std::vector<double> predicted(std::size_t(setup.unknowns), 0.0);
    for (std::size_t c = 0; c < setup.dof.size(); ++c)
      if (setup.dof[c] >= 0)
        predicted[std::size_t(setup.dof[c])] = scale * node_displacement_[c / 2][int(c % 2)];
    Trial predicted_trial;
    if (evaluate(setup, predicted, gravity, traction, body_step, true, predicted_trial, result) &&
        predicted_trial.residual.norm() < trial.residual.norm()) {
      du.swap(predicted);
      trial = std::move(predicted_trial);
    }
  }
  record.initial_residual = trial.residual.norm();
  record.reference_force = trial.reference_force;
  const double tolerance = settings_.force_tolerance;
  auto force_converged = [&](const Trial& t) {
    return t.residual.norm() <= tolerance * std::max(t.reference_force, 1.0e-300);
  };
  if (setup.unknowns == 0 || force_converged(trial)) {
    record.converged = true;
    commit(setup, du, trial, gravity, traction, body_step);
    return true;
  }

  SparseMatrix matrix(setup.unknowns, setup.unknowns);
  double first_energy = 0.0;
  for (int iteration = 1; iteration <= settings_.max_iterations; ++iteration) {
    ++result.iterations;
    const auto factor_start = std::chrono::steady_clock::now();
    matrix.setFromTriplets(trial.triplets.begin(), trial.triplets.end());
    if (!linear_solver_.factorize(matrix, iteration == 1)) {
      result.seconds_factorisation += seconds_since(factor_start);
      result.message = "the Newton matrix is singular";
      last_matrix_ = matrix;
      return false;
    }
    Eigen::VectorXd step = linear_solver_.solve(-trial.residual);
    // A Newton step that moves a node by more than step_limit cells is scaled down to that:
    // where perfectly plastic soil offers a mechanism, only the contact restrains it, and an
    // iterate that has lifted the soil off a body gives a step along the mechanism of many cells.
    if (settings_.step_limit > 0.0 && step.size() > 0) {
      const double largest = step.cwiseAbs().maxCoeff();
      const double limit = settings_.step_limit * grid_.min_spacing();
      if (largest > limit) step *= limit / largest;
    }
    result.seconds_factorisation += seconds_since(factor_start);
    if (!step.allFinite()) {
      result.message = "the Newton step is not finite";
      return false;
    }
    if (iteration == 1) last_matrix_ = matrix;
    // Line search: halve the step while the residual norm does not fall. If no length lowers it,
    // the length with the smallest residual is taken (not the shortest: near a change of the
    // contact or plastic state the shortest step can raise ||R|| by orders of magnitude).
    const double before = trial.residual.norm();
    const double energy_before = std::abs(step.dot(trial.residual));
    double length = 1.0;
    Trial next, best;
    std::vector<double> best_du;
    double best_norm = std::numeric_limits<double>::infinity(), best_length = 1.0;
    for (int attempt = 0; attempt <= settings_.line_search_steps; ++attempt) {
      std::vector<double> candidate = du;
      for (int d = 0; d < setup.unknowns; ++d) candidate[std::size_t(d)] += length * step[d];
      if (evaluate(setup, candidate, gravity, traction, body_step, true, next, result)) {
        const double norm = next.residual.norm();
        if (norm < best_norm) {
          best_norm = norm;
          best_length = length;
          best_du.swap(candidate);
          std::swap(best, next);
        }
        if (norm < before) break;
      }
      length *= 0.5;
    }
    if (!std::isfinite(best_norm)) {
      result.message = "a stress update failed in the iterations";
      return false;
    }
    du.swap(best_du);
    next = std::move(best);
    length = best_length;
    IterationRecord iteration_record;
    for (std::size_t c = 0; c < next.corner.size(); ++c) {
      const PointContact& now = next.corner[c];
      const PointContact& was = trial.corner[c];
      iteration_record.contact_points += now.active ? 1 : 0;
      iteration_record.slipping_points += now.slip ? 1 : 0;
      if (now.active != was.active || now.slip != was.slip) ++iteration_record.contact_changes;
    }
    trial = std::move(next);
    iteration_record.floor_particles = trial.floor_particles;
    iteration_record.residual_norm = trial.residual.norm();
    iteration_record.energy_norm = std::abs(length * step.dot(trial.residual));
    iteration_record.line_search = length;
    if (iteration == 1) first_energy = energy_before;
    record.iterations.push_back(iteration_record);
    const bool energy_converged =
        iteration_record.energy_norm <= settings_.energy_tolerance * std::max(first_energy, 1e-300);
    if (force_converged(trial) && energy_converged) {
      record.converged = true;
      commit(setup, du, trial, gravity, traction, body_step);
      return true;
    }
    if (iteration_record.residual_norm > 1.0e8 * std::max(record.initial_residual, 1e-300)) {
      result.message = "the Newton iterations diverge";
      return false;
    }
  }
  result.message = fmt::format("no convergence in {} iterations", settings_.max_iterations);
  return false;
}

void QuasiStaticSolver::commit(const StepSetup& setup, const std::vector<double>& du,
                               const Trial& trial, double gravity, double traction,
                               const std::vector<Vec2>& body_step) {
  (void)du;
  Particles& p = particles_;
  const std::size_t count = p.size();
  const bool stretch_domains = settings_.shape_function == ShapeFunction::cpgimp;
  // Work over the step (trapezoidal in the stress and the load factor).
  const double gravity_mean = 0.5 * (gravity + gravity_multiplier_) * settings_.gravity;
  const double traction_mean = 0.5 * (traction + traction_multiplier_);
  for (std::size_t i = 0; i < count; ++i) {
    const ParticleNodes& pn = setup.nodes[i];
    Vec2 displacement = Vec2::Zero();
    for (int k = 0; k < pn.count; ++k)
      displacement += pn.weight[k] * trial.node_displacement[std::size_t(pn.node[k])];
    energies_.internal +=
        0.5 * p.volume[i] *
        (p.state[i].stress + trial.state[i].stress).dot(trial.strain_increment[i]);
    energies_.external_work +=
        (traction_mean * p.external_force[i] - Vec2(0.0, p.mass[i] * gravity_mean))
            .dot(displacement);
    for (int q = 0; q < kCorners; ++q) {
      Vec2& corner = corner_position_[i * kCorners + std::size_t(q)];
      corner += displacement + trial.gradient[i] * (corner - p.position[i]);
    }
    p.position[i] += displacement;
    p.state[i] = trial.state[i];
    Mat2& deformation = p.deformation_gradient[i];
    deformation = (Mat2::Identity() + trial.gradient[i]) * deformation;
    p.out_of_plane_stretch[i] *= 1.0 + trial.hoop[i];
    p.volume[i] = deformation.determinant() * p.out_of_plane_stretch[i] * p.initial_volume[i];
    // cpGIMP: the domain follows the stretch, as in the explicit solver.
    if (stretch_domains) p.half_size[i] = stretched_half_size(p.initial_half_size[i], deformation);
    if (!grid_.contains(p.position[i].x(), p.position[i].y()) ||
        (settings_.geometry == Geometry::axisymmetric && !(p.position[i].x() > 0.0)))
      throw Error(fmt::format("quasi-static: particle {} left the grid at ({}, {})", i,
                              p.position[i].x(), p.position[i].y()));
  }
  // Contact: forces on the bodies, histories, the largest penetration.
  std::vector<BodyForce> forces = body_forces_;
  for (BodyForce& f : forces) {
    f.total.setZero();
    for (Vec2& part : f.parts) part.setZero();
  }
  max_penetration_ = 0.0;
  for (std::size_t c = 0; c < trial.corner.size(); ++c) {
    const PointContact& point = trial.corner[c];
    ContactHistory& history = contact_history_[c];
    if (!point.active) {
      history = ContactHistory{};
      continue;
    }
    const int body = trial.corner_body[c];
    BodyForce& f = forces[std::size_t(body)];
    f.total -= point.force;
    f.parts[std::size_t(trial.corner_part[c])] -= point.force;
    max_penetration_ = std::max(max_penetration_, -trial.corner_gap[c]);
    history.body = body;
    history.tangential_force = point.tangential_vector;
  }
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    energies_.contact_work += 0.5 * (body_forces_[b].total + forces[b].total).dot(-body_step[b]);
    bodies_[b].translate(body_step[b]);
  }
  body_forces_ = std::move(forces);
  // The reaction of the constraints on the soil: the residual f_int - f_ext - f_contact at the
  // constrained components (what the constraint has to add for equilibrium there).
  boundary_reaction_.setZero();
  for (std::size_t c = 0; c < trial.internal.size(); ++c)
    if (setup.active[c / 2] && setup.dof[c] < 0)
      boundary_reaction_[int(c % 2)] += trial.internal[c] - trial.external[c] - trial.contact[c];
  node_displacement_ = trial.node_displacement;
  last_body_step_ = 0.0;
  for (const Vec2& d : body_step) last_body_step_ = std::max(last_body_step_, d.norm());
  gravity_multiplier_ = gravity;
  traction_multiplier_ = traction;
}

LoadStepResult QuasiStaticSolver::solve_step(const LoadStep& load) {
  LoadStepResult result;
  if (!load.body_displacement.empty() && load.body_displacement.size() != bodies_.size())
    throw InvalidValue("load step body displacements",
                       std::to_string(load.body_displacement.size()),
                       fmt::format("0 or {} (one per rigid body)", bodies_.size()));
  // The state at the start of the step, restored if the step fails.
  const Particles start_particles = particles_;
  const std::vector<RigidBody> start_bodies = bodies_;
  const std::vector<BodyForce> start_forces = body_forces_;
  const std::vector<ContactHistory> start_history = contact_history_;
  const std::vector<Vec2> start_corners = corner_position_;
  const std::vector<Vec2> start_node_displacement = node_displacement_;
  const double start_body_step = last_body_step_;
  const double start_gravity = gravity_multiplier_, start_traction = traction_multiplier_;
  const Energies start_energies = energies_;
  const Vec2 start_reaction = boundary_reaction_;
  const double start_penetration = max_penetration_;
  if (std::all_of(contact_modulus_.begin(), contact_modulus_.end(),
                  [](double m) { return m == 0.0; }))
    fix_contact_modulus();

  double done = 0.0, size = 1.0;
  LoadStep remaining = load;
  while (done < 1.0 - 1.0e-12) {
    size = std::min(size, 1.0 - done);
    // The sub-increment as a fraction of what remains of the step.
    const double share = size / (1.0 - done);
    SubIncrementRecord record;
    record.fraction = size;
    LoadStep part = remaining;
    const bool converged = solve_sub_increment(share, part, record, result);
    result.sub_increments.push_back(record);
    if (converged) {
      for (Vec2& d : remaining.body_displacement) d *= 1.0 - share;
      done += size;
      if (int(record.iterations.size()) <= settings_.easy_iterations) size *= 2.0;
      continue;
    }
    if (result.cuts >= settings_.max_cuts) {
      particles_ = start_particles;
      bodies_ = start_bodies;
      body_forces_ = start_forces;
      contact_history_ = start_history;
      corner_position_ = start_corners;
      node_displacement_ = start_node_displacement;
      last_body_step_ = start_body_step;
      gravity_multiplier_ = start_gravity;
      traction_multiplier_ = start_traction;
      energies_ = start_energies;
      boundary_reaction_ = start_reaction;
      max_penetration_ = start_penetration;
      result.converged = false;
      result.message = fmt::format("no convergence after {} cuts ({} done of the step): {}",
                                   result.cuts, format_value(done), result.message);
      return result;
    }
    ++result.cuts;
    size *= 0.5;
  }
  result.converged = true;
  result.message.clear();
  time_ += load.duration;
  ++steps_;
  return result;
}

namespace {

constexpr const char* kCornerPositions = "contact_corner_position_m";
constexpr const char* kCornerForces = "contact_tangential_force_N";
constexpr const char* kCornerBodies = "contact_body";
constexpr const char* kNodeDisplacements = "last_node_displacement_m";
// gravity multiplier, traction multiplier, last body step [m], largest penetration [m],
// boundary reaction x, y [N] (the work account is the run state's energies)
constexpr const char* kLoad = "quasi_static_load";
constexpr const char* kContactModulus = "contact_modulus_Pa";  // per material (0: not fixed)

std::vector<double> flat(const std::vector<Vec2>& v) {
  std::vector<double> out;
  out.reserve(2 * v.size());
  for (const Vec2& x : v) {
    out.push_back(x.x());
    out.push_back(x.y());
  }
  return out;
}

}  // namespace

SolverRunState QuasiStaticSolver::run_state() const {
  SolverRunState state;
  state.time = time_;
  state.steps = steps_;
  state.energies = energies_;
  state.rigid_body_forces = body_forces_;
  std::vector<double> forces, bodies;
  for (const ContactHistory& h : contact_history_) {
    forces.push_back(h.tangential_force.x());
    forces.push_back(h.tangential_force.y());
    bodies.push_back(h.body);
  }
  state.scheme_arrays = {{kCornerPositions, flat(corner_position_)},
                         {kCornerForces, std::move(forces)},
                         {kCornerBodies, std::move(bodies)},
                         {kNodeDisplacements, flat(node_displacement_)},
                         {kLoad,
                          {gravity_multiplier_, traction_multiplier_, last_body_step_,
                           max_penetration_, boundary_reaction_.x(), boundary_reaction_.y()}},
                         {kContactModulus, contact_modulus_}};
  return state;
}

void QuasiStaticSolver::restore_run_state(const SolverRunState& state) {
  auto array = [&](const char* name, std::size_t size) -> const std::vector<double>& {
    for (const auto& [key, values] : state.scheme_arrays)
      if (key == name) {
        if (values.size() != size)
          throw InvalidValue(fmt::format("quasi-static run state {}", name),
                             std::to_string(values.size()), std::to_string(size));
        return values;
      }
    throw InvalidValue("quasi-static run state", "no array " + std::string(name),
                       "the arrays of a quasi-static checkpoint");
  };
  const std::size_t corners = particles_.size() * kCorners;
  const std::size_t nodes = std::size_t(grid_.node_count());
  if (state.rigid_body_forces.size() != bodies_.size())
    throw InvalidValue("rigid body forces in the run state",
                       std::to_string(state.rigid_body_forces.size()),
                       fmt::format("{} (one per rigid body)", bodies_.size()));
  const std::vector<double>& positions = array(kCornerPositions, 2 * corners);
  const std::vector<double>& forces = array(kCornerForces, 2 * corners);
  const std::vector<double>& bodies = array(kCornerBodies, corners);
  const std::vector<double>& displacements = array(kNodeDisplacements, 2 * nodes);
  const std::vector<double>& load = array(kLoad, 6);
  contact_modulus_ = array(kContactModulus, materials_.size());
  contact_history_.assign(corners, ContactHistory{});
  corner_position_.resize(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    corner_position_[c] = Vec2(positions[2 * c], positions[2 * c + 1]);
    contact_history_[c].tangential_force = Vec2(forces[2 * c], forces[2 * c + 1]);
    contact_history_[c].body = static_cast<int>(bodies[c]);
  }
  node_displacement_.resize(nodes);
  for (std::size_t n = 0; n < nodes; ++n)
    node_displacement_[n] = Vec2(displacements[2 * n], displacements[2 * n + 1]);
  gravity_multiplier_ = load[0];
  traction_multiplier_ = load[1];
  last_body_step_ = load[2];
  max_penetration_ = load[3];
  boundary_reaction_ = Vec2(load[4], load[5]);
  energies_ = state.energies;
  body_forces_ = state.rigid_body_forces;
  time_ = state.time;
  steps_ = state.steps;
}

}  // namespace pilempm::mpm::quasi_static
