// Internal to the quasi-static solver (not installed API): what the iterations of a load step
// share and what evaluating one iterate yields, and the small helpers the solver's files use.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <vector>

#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"
#include "pilempm/mpm/quasi_static/rounded_surface.hpp"

namespace pilempm::mpm::quasi_static {

namespace detail {

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
inline Mat4 in_plane(const Mat6& full) {
  Mat4 d;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) d(r, c) = full(kComponents[r], kComponents[c]);
  return d;
}

// The motion of the body that moves most in an increment (zero where none moves).
inline Vec2 largest_motion(const std::vector<Vec2>& body_step) {
  Vec2 motion = Vec2::Zero();
  for (const Vec2& d : body_step)
    if (d.squaredNorm() > motion.squaredNorm()) motion = d;
  return motion;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Trial::fixed_stress's values.
constexpr char kNotFixed = 0, kOnFloor = 1, kAtApex = 2;

// The weights of a particle's stencil as a flat list of nodes (row-major over the stencil).
struct ParticleNodes {
  int count = 0;
  int node[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
  double weight[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
  Vec2 gradient[AxisWeights::kMaxNodes * AxisWeights::kMaxNodes];
};

inline void flatten(const Stencil& stencil, int nx, ParticleNodes& out) {
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
inline void node_share(const GridAxis& axis, int i, double& lo, double& hi) {
  lo = i > 0 ? 0.5 * (axis.node(i - 1) + axis.node(i)) : axis.node(i);
  hi = i + 1 < axis.node_count() ? 0.5 * (axis.node(i) + axis.node(i + 1)) : axis.node(i);
}

}  // namespace detail

// What the iterations of one sub-increment share: the reference configuration's stencils and
// the unknowns.
struct QuasiStaticSolver::StepSetup {
  std::vector<detail::ParticleNodes> nodes;  // per particle
  std::vector<int> dof;                      // per node component (2 per node): unknown index or -1
  std::vector<char> active;                  // per node
  int unknowns = 0;
  std::vector<char> near_body;  // per particle: whether its corners are checked for contact
  struct GhostSpring {
    int node_a, node_b;
    double stiffness;
  };
  std::vector<GhostSpring> ghosts;
  std::vector<detail::RoundedSurface> surfaces;  // per body, at its start-of-increment position
  // Volumetric averaging (Settings::volumetric_averaging): per cell, the nodes its particles
  // reach and the volume-weighted mean volumetric row b̄ (x, y per node); per particle its cell
  // and where each of its nodes sits in the cell's list.
  struct CellMean {
    int count = 0;
    int node[detail::kMaxCellNodes];
    Vec2 row[detail::kMaxCellNodes];
  };
  std::vector<CellMean> cells;
  std::vector<int> cell;                  // per particle
  std::vector<std::array<int, 16>> slot;  // per particle and stencil node
  // The Newton matrix's pattern, fixed over the sub-increment's iterations (compressed, values
  // zero): every pair of unknowns of a particle's B columns (its cell's nodes with volumetric
  // averaging, else its own), which holds the contact's pairs too, and the ghost springs' pairs.
  // A scatter block is a cell with volumetric averaging (its particles share their columns), else
  // a particle; block b's map gives, for its local columns l = 2 j + component over its nodes j,
  // the pattern entry of (row l_r, column l_c) at scatter[scatter_offset[b] + l_c * 2w + l_r]
  // (w its nodes), or -1 where either component is not an unknown.
  SparseMatrix pattern;
  std::vector<int> block;                   // per particle
  std::vector<std::size_t> scatter_offset;  // per block, and one past the last
  std::vector<int> scatter;
  std::vector<std::array<int, 4>> ghost_entry;  // per ghost spring: (a,a), (b,b), (a,b), (b,a)
  // The nodes of block b and their number.
  const int* block_nodes(int b, int& width) const {
    if (cells.empty()) {
      width = nodes[std::size_t(b)].count;
      return nodes[std::size_t(b)].node;
    }
    width = cells[std::size_t(b)].count;
    return cells[std::size_t(b)].node;
  }
};

// The results of evaluating one iterate.
struct QuasiStaticSolver::Trial {
  std::vector<MaterialState> state;
  std::vector<SubstepPath> path;  // the sub-steps of each state's update (the tangent's probes)
  std::vector<Vec6> strain_increment;
  std::vector<Mat2> gradient;  // G = Σ Δu_i ⊗ ∇S_i
  std::vector<double> hoop;
  std::vector<detail::Mat4> tangent;
  // Per particle: the derivative of its stress (11, 22, 33, 12) with respect to its spin
  // increment w = ½(G_yx − G_xy), through the Hughes-Winget rotation of the converged state.
  std::vector<detail::Vec4> spin_tangent;
  std::vector<Vec2> node_displacement;              // per node
  std::vector<double> internal, external, contact;  // per node component
  std::vector<PointContact> corner;                 // per particle corner
  std::vector<int> corner_body, corner_part;        // per particle corner
  std::vector<double> corner_gap;                   // per particle corner
  Eigen::VectorXd residual;                         // per unknown
  // The Newton matrix on StepSetup::pattern, by part (for the check by parts, check_tangent):
  // the material's values per pattern entry, the contact's and the ghost springs' entries.
  std::vector<double> material_values;
  struct Entry {
    int index, row, column;  // the pattern entry and its place
    double value;
  };
  std::vector<Entry> contact_entries, ghost_entries;
  bool has_matrix = false;
  // The stresses above are those of the iterate in node_displacement (a successful evaluation),
  // with fixed_stress per particle: an evaluation of the same iterate for its matrix reuses them.
  bool has_states = false;
  // Per particle, whether its update ended with a stress that no longer changes with the strain:
  // kOnFloor (the model's mean stress floor), kAtApex (an apex of its yield surface), kNotFixed.
  std::vector<char> fixed_stress;
  /// The low-stress stabilisation's stress of each particle (Settings::low_stress_stiffness),
  /// added to the model's in the internal force; not kept past the sub-increment. Empty without
  /// the stabilisation.
  std::vector<Vec6> stabilising_stress;
  double reference_force = 0.0;
  int floor_particles = 0;    // stress updates that ended on the floor or at an apex
  long failed_particle = -1;  // the first particle whose stress update failed, or -1
  const char* failure = "";   // its model's reason

  // Records a particle whose update failed, from the evaluation's parallel particle loop: the
  // one with the smallest index is kept, whatever the threads' order.
  void record_failure(long particle, const char* reason) {
#pragma omp critical(quasi_static_failed_update)
    if (failed_particle < 0 || particle < failed_particle) {
      failed_particle = particle;
      failure = reason;
    }
  }

  // The Newton matrix's values into `matrix`, a copy of the set-up's pattern.
  void fill(SparseMatrix& matrix) const {
    double* value = matrix.valuePtr();
    std::copy(material_values.begin(), material_values.end(), value);
    for (const Entry& e : contact_entries) value[e.index] += e.value;
    for (const Entry& e : ghost_entries) value[e.index] += e.value;
  }
};

// The particles' tangents differentiated in a sub-increment, with the strain and spin increments
// they were differentiated at (Settings::tangent_reuse); valid: differentiated, not a floor's or a
// closed form's.
struct QuasiStaticSolver::TangentCache {
  std::vector<detail::Mat4> tangent;
  std::vector<Vec6> strain;
  std::vector<double> spin;
  std::vector<char> valid;
};

}  // namespace pilempm::mpm::quasi_static
