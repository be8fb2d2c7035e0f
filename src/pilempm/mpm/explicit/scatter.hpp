#pragma once
// The lock-free, deterministic scatter from the particles to the grid, and the nodal scratch the
// stages of the explicit step share.
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/shape_functions.hpp"

namespace pilempm::mpm {

/// One node's sums in a thread's buffer, the x and y components side by side (SIMD pairs).
struct NodeSums {
  Vec2 momentum = Vec2::Zero();
  Vec2 force = Vec2::Zero();
  double mass = 0.0;
};

/// The nodal velocity and its change over the step side by side, for the gathers: a copy of the
/// grid's velocity_x, _y and velocity_change_x, _y, kept equal to them within a step.
struct NodeMotion {
  Vec2 velocity = Vec2::Zero();
  Vec2 change = Vec2::Zero();
};

/// Which nodal sums a scatter forms: the momentum alone (the MUSL remap, XPIC), or also the mass
/// and the force (particles to grid).
enum class ScatterSums { momentum, mass_momentum_force };

/// Scatter without locks: each thread adds into its own buffer, and then each node's sum is
/// formed from the buffers in thread order (over the node range each thread touched), which also
/// clears them. A run is thus deterministic for a given thread count.
class NodeScatter {
 public:
  /// Buffers for `threads` threads on a grid of `node_count` nodes.
  void resize(int threads, int node_count) {
    buffers_.resize(static_cast<std::size_t>(threads));
    for (ThreadBuffer& buffer : buffers_)
      buffer.sums.assign(static_cast<std::size_t>(node_count), NodeSums{});
  }

  /// One parallel pass: scatter_particle(p, sums, thread) adds particle p's share into the
  /// thread's buffer and leaves its stencil in stencils[p]; then, node by node, the sums go to the
  /// grid's nodal fields and finish_node(n, thread) runs once node n's sums are complete.
  template <class ScatterParticle, class FinishNode>
  void run(Grid& grid, const std::vector<Stencil>& stencils, ScatterSums which,
           ScatterParticle&& scatter_particle, FinishNode&& finish_node) {
    const bool mass_and_force = which == ScatterSums::mass_momentum_force;
    NodalFields& nodes = grid.nodes();
    const long node_count = grid.node_count();
    const auto particle_count = static_cast<long>(stencils.size());
    const int nx = grid.nx();
#pragma omp parallel num_threads(static_cast <int>(buffers_.size()))
    {
      const int thread = omp_get_thread_num();
      NodeSums* const sums = buffers_[static_cast<std::size_t>(thread)].sums.data();
      int lowest_node = static_cast<int>(node_count), end_node = 0;
#pragma omp for schedule(static)
      for (long p = 0; p < particle_count; ++p) {
        scatter_particle(p, sums, thread);
        const Stencil& stencil = stencils[p];
        const int first = stencil.y.first * nx + stencil.x.first;
        lowest_node = std::min(lowest_node, first);
        end_node = std::max(end_node, first + (stencil.y.count - 1) * nx + stencil.x.count);
      }
      buffers_[static_cast<std::size_t>(thread)].lowest_node = lowest_node;
      buffers_[static_cast<std::size_t>(thread)].end_node = end_node;
#pragma omp barrier
      const int team = omp_get_num_threads();
#pragma omp for schedule(static)
      for (long n = 0; n < node_count; ++n) {
        Vec2 momentum = Vec2::Zero(), force = Vec2::Zero();
        double mass = 0.0;
        for (int t = 0; t < team; ++t) {
          ThreadBuffer& buffer = buffers_[static_cast<std::size_t>(t)];
          if (n < buffer.lowest_node || n >= buffer.end_node) continue;
          NodeSums& node = buffer.sums[static_cast<std::size_t>(n)];
          momentum += node.momentum;
          node.momentum.setZero();
          if (mass_and_force) {
            mass += node.mass;
            force += node.force;
            node.mass = 0.0;
            node.force.setZero();
          }
        }
        nodes.momentum_x[n] = momentum.x();
        nodes.momentum_y[n] = momentum.y();
        if (mass_and_force) {
          nodes.mass[n] = mass;
          nodes.force_x[n] = force.x();
          nodes.force_y[n] = force.y();
        }
        finish_node(n, thread);
      }
    }
  }

 private:
  // A thread's nodal sums, and the node range it touched.
  struct ThreadBuffer {
    std::vector<NodeSums> sums;
    int lowest_node = 0, end_node = 0;
  };
  std::vector<ThreadBuffer> buffers_;
};

}  // namespace pilempm::mpm
