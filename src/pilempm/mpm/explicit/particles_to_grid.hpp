#pragma once
// Particles to grid, the first pass of the explicit step: each particle's weights at x^n and its
// share of the nodal mass, momentum and force.
#include "pilempm/mpm/explicit/scatter.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/shape_functions.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

class ParticlesToGrid {
 public:
  /// `stencils` and `start_radius` (axisymmetry): per particle, written by weights().
  ParticlesToGrid(const Grid& grid, const Particles& particles, ShapeFunction shape,
                  bool axisymmetric, double mass_scaling, const Vec2& gravity, Stencil* stencils,
                  double* start_radius)
      : grid_(grid),
        particles_(particles),
        shape_(shape),
        axisymmetric_(axisymmetric),
        nx_(grid.nx()),
        mass_scaling_(mass_scaling),
        gravity_(gravity),
        stencils_(stencils),
        start_radius_(start_radius) {}

  /// The weights of particle i at x^n (and its radius r^n in axisymmetry), kept for the step: the
  /// stress update needs both after the particles have moved.
  void weights(long i) const {
    const Vec2& x = particles_.position[i];
    compute_stencil(grid_, shape_, x.x(), x.y(), particles_.half_size[i].x(),
                    particles_.half_size[i].y(), stencils_[i]);
    if (axisymmetric_) start_radius_[i] = x.x();
  }

  /// Particle i's share of the nodal mass (inertial), momentum and force into a thread's sums:
  /// f_i = S_i b_p - V_p σ_p ∇S_i, and in axisymmetry the hoop stress pulls the radial nodes by
  /// -V σ_θθ S_i / r_p.
  void scatter(long i, NodeSums* to) const {
    const Particles& p = particles_;
    const Stencil& stencil = stencils_[i];
    const Vec2& x = p.position[i];
    const double inertial_mass = mass_scaling_ * p.mass[i];
    const Vec2 momentum = inertial_mass * p.velocity[i];
    const Vec2 body_force = p.mass[i] * gravity_ + p.external_force[i];
    const Vec6& stress = p.state[i].stress;
    const double volume = p.volume[i];
    const double v_sxx = volume * stress[k11], v_syy = volume * stress[k22];
    const double v_sxy = volume * stress[k12] / kSqrt2;
    const double hoop_force = axisymmetric_ ? -volume * stress[k33] / x.x() : 0.0;
    const double radial_force = body_force.x() + hoop_force;
    for_each_row(stencil, nx_, [&](int row, auto row_nodes, double weight_y, double gradient_y) {
      // With S_i = S_x S_y, ∇S_i = (S_x' S_y, S_x S_y'): per row, the coefficients of S_x and
      // S_x'.
      const double row_mass = weight_y * inertial_mass;
      const Vec2 row_momentum = weight_y * momentum;
      const Vec2 force_weight(weight_y * radial_force - gradient_y * v_sxy,
                              weight_y * body_force.y() - gradient_y * v_syy);
      const Vec2 force_gradient(-weight_y * v_sxx, -weight_y * v_sxy);
      for (int k = 0; k < row_nodes; ++k) {
        NodeSums& node = to[row + k];
        const double weight_x = stencil.x.weight[k], gradient_x = stencil.x.gradient[k];
        node.mass += weight_x * row_mass;
        node.momentum += weight_x * row_momentum;
        node.force += weight_x * force_weight + gradient_x * force_gradient;
      }
    });
  }

 private:
  const Grid& grid_;
  const Particles& particles_;
  ShapeFunction shape_;
  bool axisymmetric_;
  int nx_;
  double mass_scaling_;
  Vec2 gravity_;
  Stencil* stencils_;
  double* start_radius_;
};

}  // namespace pilempm::mpm
