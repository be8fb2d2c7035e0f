// Rigid-body contact of the explicit step, on the nodal velocities.
#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/explicit/grid_update.hpp"
#include "pilempm/mpm/explicit/solver.hpp"

namespace pilempm::mpm {

int Solver::add_rigid_body(RigidBody body) {
  const bool axisymmetric = settings_.geometry == Geometry::axisymmetric;
  if (body.axisymmetric() != axisymmetric)
    throw InvalidValue("rigid body", body.axisymmetric() ? "pile" : "polygon",
                       axisymmetric ? "a pile in axisymmetry" : "a polygon in plane strain");
  RigidBodyForce force;
  force.parts.assign(static_cast<std::size_t>(body.part_count()), Vec2::Zero());
  rigid_bodies_.push_back(std::move(body));
  rigid_body_forces_.push_back(std::move(force));
  return static_cast<int>(rigid_bodies_.size()) - 1;
}

// Rigid-body form of the multi-velocity contact of Bardenhagen, Brackbill & Sulsky (2000) and
// Bardenhagen et al. (2001): the body is a second velocity field of infinite mass, so the centre
// of mass velocity at a node is the body's. At a node with soil mass inside the body or closer
// than the contact distance (half the smallest cell by default: the nodes of the cell row that
// touches the surface, but not the next row) whose soil velocity approaches the body:
//   v_rel = v_i - v_body, v_n = v_rel . n < 0 (approaching; v_n >= 0 separates freely)
//   Δv = -v_n n - min(|v_t|, μ |v_n|) v_t / |v_t|, v_t = v_rel - v_n n   (Coulomb: stick or slip)
// At a node with one constrained component (the axis, a roller) the free component alone meets
// v_rel . n = 0, without friction; a node with both constrained is left alone. The force on the
// body is -Σ_i m_i Δv_i / Δt, in total and per surface part of the nearest surface point.
// The nodes are visited serially over the body's bounding box, so the sums are deterministic.
void Solver::apply_contact(double dt, ContactPass pass) {
  if (rigid_bodies_.empty()) return;
  const bool forces = pass == ContactPass::after_grid_update;
  NodalFields& nodes = grid_.nodes();
  const double* free_x = grid_.free_x().data();
  const double* free_y = grid_.free_y().data();
  const GridAxis& x_axis = grid_.x_axis();
  const GridAxis& y_axis = grid_.y_axis();
  const int nx = grid_.nx();
  const double alpha = settings_.local_damping;
  for (std::size_t b = 0; b < rigid_bodies_.size(); ++b) {
    const RigidBody& body = rigid_bodies_[b];
    RigidBodyForce& force = rigid_body_forces_[b];
    if (forces) {
      force.total.setZero();
      for (Vec2& part : force.parts) part.setZero();
    }
    const double reach =
        body.contact_distance() > 0.0 ? body.contact_distance() : 0.5 * grid_.min_spacing();
    const Vec2 low = body.box_min() - Vec2::Constant(reach);
    const Vec2 high = body.box_max() + Vec2::Constant(reach);
    if (high.x() < x_axis.start() || low.x() > x_axis.end() || high.y() < y_axis.start() ||
        low.y() > y_axis.end())
      continue;
    const int i_first = x_axis.cell_of(low.x()), i_last = x_axis.cell_of(high.x()) + 1;
    const int j_first = y_axis.cell_of(low.y()), j_last = y_axis.cell_of(high.y()) + 1;
    const Vec2& body_velocity = body.velocity();
    const double friction = body.friction();
    for (int j = j_first; j <= j_last; ++j) {
      for (int i = i_first; i <= i_last; ++i) {
        const int n = j * nx + i;
        const double mass = nodes.mass[n];
        if (mass <= 0.0) continue;
        const SurfaceQuery surface = body.query(Vec2(x_axis.node(i), y_axis.node(j)));
        if (surface.distance >= reach) continue;
        double damped_work = 0.0;
        // The local damping of the grid update does not act at a contact node: the body sets its
        // velocity, as a support does (else the damping force would add to the contact force,
        // by about the factor 1 + α). Its share of v^L is taken out again (not at dashpots).
        Vec2 damping_change = Vec2::Zero();
        if (forces && alpha > 0.0 &&
            (dashpot_x_.empty() || (dashpot_x_[n] == 0.0 && dashpot_y_[n] == 0.0))) {
          const Vec2 old_velocity = Vec2(nodes.momentum_x[n], nodes.momentum_y[n]) / mass;
          const Vec2 damping_force(local_damping_force(alpha, nodes.force_x[n], old_velocity.x()),
                                   local_damping_force(alpha, nodes.force_y[n], old_velocity.y()));
          damping_change =
              Vec2(free_x[n] * damping_force.x(), free_y[n] * damping_force.y()) * (dt / mass);
          damped_work =
              -0.5 * dt *
              damping_force.dot(old_velocity + Vec2(nodes.velocity_x[n], nodes.velocity_y[n]));
        }
        const Vec2 undamped = Vec2(nodes.velocity_x[n], nodes.velocity_y[n]) - damping_change;
        const Vec2 relative = undamped - body_velocity;
        const double normal_speed = relative.dot(surface.normal);
        if (normal_speed >= 0.0) continue;  // separating or sliding along: no contact
        Vec2 change = Vec2::Zero();
        if (free_x[n] > 0.0 && free_y[n] > 0.0) {
          const Vec2 tangential = relative - normal_speed * surface.normal;
          const double slip = tangential.norm();
          change = -normal_speed * surface.normal;  // the body's normal velocity wins
          // Coulomb: the tangential correction is at most μ times the normal one (stick below).
          if (slip > 0.0) change -= std::min(slip, -friction * normal_speed) / slip * tangential;
        } else if (free_x[n] > 0.0 || free_y[n] > 0.0) {
          // One free component (the axis, a roller): it alone stops the approach, v_rel . n = 0,
          // without friction; a normal across the free direction is held by the constraint.
          const Vec2 free_direction = free_x[n] > 0.0 ? Vec2(1.0, 0.0) : Vec2(0.0, 1.0);
          const double along = free_direction.dot(surface.normal);
          if (std::abs(along) > 1e-3) change = -normal_speed / along * free_direction;
        }
        nodes.velocity_x[n] = undamped.x() + change.x();
        nodes.velocity_y[n] = undamped.y() + change.y();
        node_motion_[static_cast<std::size_t>(n)].velocity += change - damping_change;
        if (forces) {
          nodes.velocity_change_x[n] += change.x() - damping_change.x();
          nodes.velocity_change_y[n] += change.y() - damping_change.y();
          node_motion_[static_cast<std::size_t>(n)].change += change - damping_change;
          energies_.damping -= damped_work;
          damping_force_ -= damping_change * (mass / dt);  // the contact took it out
          const Vec2 on_body = -mass * change / dt;
          force.total += on_body;
          force.parts[static_cast<std::size_t>(surface.part)] += on_body;
          // The work of the body on the soil: its force on the soil along its own velocity.
          energies_.contact_work -= on_body.dot(body_velocity) * dt;
        }
      }
    }
  }
}

}  // namespace pilempm::mpm
