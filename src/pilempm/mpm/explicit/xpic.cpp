// XPIC(m): the extended PIC share of the explicit step's particle velocity update.
#include "pilempm/mpm/explicit/solver.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

// XPIC(m) (Hammerquist & Nairn 2017, "A new method for material point method particle updates
// that reduces noise and enhances stability"). With the particle-to-grid map S+ (mass-weighted)
// and the grid-to-particle map S, PIC sets V^n+1 = S v^L = S S+ V^n + S Δv. XPIC(m) replaces the
// smoothing S S+ by 1 - (1 - S S+)^m, which on the grid is S v* with
//   v* = Σ_k=1..m (-1)^(k+1) C(m, k) (S+ S)^(k-1) v^n,  v^n = S+ V^n (the grid velocity before
// the update). m = 1 gives PIC; as m grows, only the null space of S+ (the noise) is removed.
// Each power of S+ S is one gather to the particles and one mass-weighted scatter back, with the
// boundary conditions of the grid applied after each. The coefficients sum to 1, so a rigid
// translation is kept. The nodal momentum is used as the scatter's buffer and restored after.
void Solver::compute_xpic_shift() {
  NodalFields& nodes = grid_.nodes();
  const auto node_count = static_cast<std::size_t>(grid_.node_count());
  const double* free_x = grid_.free_x().data();
  const double* free_y = grid_.free_y().data();
  const int nx = grid_.nx();
  const int order = settings_.xpic_order;
  const double mass_scaling = settings_.mass_scaling;
  xpic_start_.resize(node_count);
  xpic_power_.resize(node_count);
  xpic_shift_.resize(node_count);
  Vec2* start = xpic_start_.data();
  Vec2* power = xpic_power_.data();
  Vec2* sum = xpic_shift_.data();  // Σ c_k (S+ S)^(k-1) v^n, turned into the shift at the end
  const auto nodes_long = static_cast<long>(node_count);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long n = 0; n < nodes_long; ++n) {
    const double mass = nodes.mass[n];
    const Vec2 velocity =
        mass > 0.0 ? Vec2(nodes.momentum_x[n] / mass, nodes.momentum_y[n] / mass) : Vec2::Zero();
    start[n] = velocity;
    power[n] = Vec2(free_x[n] * velocity.x(), free_y[n] * velocity.y());
    sum[n] = order * power[n];  // c_1 = m
  }
  double coefficient = order;
  for (int k = 2; k <= order; ++k) {
    // c_k = (-1)^(k+1) C(m, k) = -c_(k-1) (m - k + 1) / k
    coefficient = -coefficient * (order - k + 1) / k;
    scatter_.run(
        grid_, stencils_, ScatterSums::momentum,
        [&](long i, NodeSums* to, int) {
          Vec2 velocity = Vec2::Zero();
          for_each_node(stencils_[i], nx,
                        [&](int n, double s, double, double) { velocity += s * power[n]; });
          const Vec2 momentum = mass_scaling * particles_.mass[i] * velocity;
          for_each_node(stencils_[i], nx,
                        [&](int n, double s, double, double) { to[n].momentum += s * momentum; });
        },
        [&](long n, int) {
          const double mass = nodes.mass[n];
          const double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0;
          power[n] = Vec2(free_x[n] * nodes.momentum_x[n] * inverse_mass,
                          free_y[n] * nodes.momentum_y[n] * inverse_mass);
          sum[n] += coefficient * power[n];
        });
  }
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long n = 0; n < nodes_long; ++n) {
    const double mass = nodes.mass[n];
    nodes.momentum_x[n] = mass * start[n].x();
    nodes.momentum_y[n] = mass * start[n].y();
    sum[n] = Vec2(free_x[n] * (sum[n].x() - start[n].x()), free_y[n] * (sum[n].y() - start[n].y()));
  }
}

}  // namespace pilempm::mpm
