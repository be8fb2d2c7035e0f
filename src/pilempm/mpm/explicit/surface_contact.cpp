// Rigid-body contact of the explicit step at the corners of the particles' domains (contact =
// "surface"): the penalty law with Coulomb friction of the quasi-static solver
// (mpm/surface_contact.hpp, docs/quasi-static.md "Contact with the exact surface"), evaluated once
// per step at x^n and applied as an external nodal force of the grid update.
#include <algorithm>
#include <cmath>

#include "pilempm/mpm/explicit/solver.hpp"
#include "pilempm/mpm/stencil_visit.hpp"

namespace pilempm::mpm {

namespace {

constexpr int kCorners = 4;  // (-l_x, -l_y), (+l_x, -l_y), (-l_x, +l_y), (+l_x, +l_y)

}  // namespace

// Per particle near a body and per corner q = x_p + (±l_x, ±l_y) (the current GIMP domain):
//   g, n, part = the body's exact surface query at x_q (g < 0: inside);
//   k_n = β M_p A_q / d_p, A_q = l_x + l_y (times r_q in axisymmetry), d_p = 2 min(l_x⁰, l_y⁰)
//   (the domain at creation: corner_normal_stiffness),
//   M_p the material's penalty modulus: the largest wave modulus of its particles at the first
//   step, then fixed (as in the quasi-static solver), k_t = ratio k_n;
//   Δs = the corner's motion relative to the body since the last step (zero at first touch);
//   F_q = penalty_contact(g, n, Δs, f_t of the last step, k_n, k_t, μ), the force on the soil.
// F_q goes to the nodes with the coefficients of the corner's affine motion (as in the quasi-static
// solver), Σ_i c_i = 1, so the soil receives exactly Σ F_q and the body −Σ F_q, summed per surface
// part. A corner that leaves
// the body forgets its friction history. Each corner touches at most one body (the first in
// order). The corners are visited serially, so the sums are deterministic.
void Solver::apply_surface_contact(double dt) {
  if (rigid_bodies_.empty()) return;
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  const std::size_t count = particles_.size();
  if (corner_contacts_.size() != count * kCorners)
    corner_contacts_.assign(count * kCorners, CornerContact{});
  const auto nodes = static_cast<std::size_t>(grid_.node_count());
  if (surface_force_.size() != nodes) {
    surface_force_.assign(nodes, Vec2::Zero());
    surface_nodes_.clear();
  }
  for (int n : surface_nodes_) surface_force_[std::size_t(n)].setZero();
  surface_nodes_.clear();
  surface_frequency_squared_ = 0.0;
  for (RigidBodyForce& force : rigid_body_forces_) {
    force.total.setZero();
    for (Vec2& part : force.parts) part.setZero();
  }
  if (surface_contact_modulus_.size() != models_.size())
    surface_contact_modulus_ = penalty_moduli(particles_, materials_);
  const int nx = grid_.nx();
  const double beta = settings_.surface_contact.penalty_factor;
  const double tangential_ratio = settings_.surface_contact.tangential_ratio;
  // Corners this close outside a body count in the springs' frequency bound already (for the next
  // step), so that the step is short enough when they arrive.
  const double margin = grid_.min_spacing();
  for (std::size_t p = 0; p < count; ++p) {
    const Vec2& x = particles_.position[p];
    const Vec2& l = particles_.half_size[p];
    const double modulus = surface_contact_modulus_[std::size_t(particles_.material[p])];
    const double size = penalty_length(particles_.initial_half_size[p]);
    double stiffness = 0.0;  // Σ k_n of the corners near a body
    bool stencil_ready = false;
    Stencil stencil;
    for (int q = 0; q < kCorners; ++q) {
      const Vec2 offset((q & 1) ? l.x() : -l.x(), (q & 2) ? l.y() : -l.y());
      const Vec2 corner = x + offset;
      CornerContact& contact = corner_contacts_[p * kCorners + std::size_t(q)];
      bool touched = false;
      for (std::size_t b = 0; b < rigid_bodies_.size() && !touched; ++b) {
        const RigidBody& body = rigid_bodies_[b];
        const Vec2 low = body.box_min(), high = body.box_max();
        // A point within the margin of a body is within the margin of its box.
        if (corner.x() < low.x() - margin || corner.x() > high.x() + margin ||
            corner.y() < low.y() - margin || corner.y() > high.y() + margin)
          continue;
        const SurfaceQuery hit = body.query(corner);
        if (!(hit.distance < margin)) continue;
        if (!stencil_ready) {
          stencil_ready = true;
          compute_stencil(grid_, settings_.shape_function, x.x(), x.y(), l.x(), l.y(), stencil);
        }
        const double normal_stiffness = corner_normal_stiffness(
            beta, modulus, l, size, axisymmetric ? std::abs(corner.x()) : 1.0);
        stiffness += normal_stiffness;
        if (!(hit.distance < 0.0)) continue;
        touched = true;
        const Vec2 relative = corner - low;
        const bool same_body = contact.history.body == static_cast<int>(b);
        const Vec2 slip = same_body ? Vec2(relative - contact.relative_position) : Vec2::Zero();
        const Vec2 previous = same_body ? contact.history.tangential_force : Vec2::Zero();
        const PointContact point =
            penalty_contact(hit.distance, hit.normal, slip, previous, normal_stiffness,
                            tangential_ratio * normal_stiffness, body.friction());
        contact.history.body = static_cast<int>(b);
        contact.history.tangential_force = point.tangential_vector;
        contact.relative_position = relative;
        RigidBodyForce& force = rigid_body_forces_[b];
        force.total -= point.force;
        force.parts[std::size_t(hit.part)] -= point.force;
        // The work of the body on the soil: its force on the soil along its own velocity.
        energies_.contact_work += point.force.dot(body.velocity()) * dt;
        // The corner moves with the particle's affine motion: v_q = Σ_i c_i v_i,
        // c_i = S_i(x_p) + ∇S_i(x_p) · (x_q − x_p) (Σ_i c_i = 1), and its force goes to the nodes
        // with the same c_i (as in the quasi-static solver), so the springs work on the corners'
        // own motion.
        for_each_node(stencil, nx, [&](int n, double weight, double dx, double dy) {
          const double c = weight + dx * offset.x() + dy * offset.y();
          if (c == 0.0) return;
          Vec2& nodal = surface_force_[std::size_t(n)];
          if (nodal.isZero(0.0)) surface_nodes_.push_back(n);
          nodal += c * point.force;
        });
      }
      if (!touched) contact = CornerContact{};
    }
    if (stiffness > 0.0)
      surface_frequency_squared_ = std::max(
          surface_frequency_squared_, stiffness / (settings_.mass_scaling * particles_.mass[p]));
  }
}

}  // namespace pilempm::mpm
