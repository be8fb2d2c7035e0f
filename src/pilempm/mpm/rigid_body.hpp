#pragma once
// Rigid bodies of simple shape that move with a prescribed velocity and touch the soil through
// Coulomb frictional contact at the grid nodes (the solver applies the contact).
//
// Every shape is a convex polygon in the (x, y) plane, each edge labelled with a surface part:
//   plane strain: any convex polygon (a rectangle, a plate, an inclined plane as a large one);
//   axisymmetry: a pile, a cylinder of radius R on the axis with a conical or flat tip. Its
//     half-section mirrored about the axis is a convex polygon; points are queried at |r|.
// The top of a pile lies `length` above its tip, far enough to stay out of the grid.
#include <string>
#include <vector>

#include "pilempm/mpm/particles.hpp"

namespace pilempm::mpm {

/// The nearest point of a body's surface, seen from a point.
struct SurfaceQuery {
  double distance = 0.0;       ///< signed distance [m]: > 0 outside, < 0 inside
  Vec2 normal = Vec2::Zero();  ///< unit outward normal of the surface nearest the point
  int part = 0;                ///< surface part of that point (index into part_names())
  /// How fast the normal turns as the point moves along the surface [1/m]: n changes by
  /// curvature (t · dx) t, t = (−n_y, n_x). 1/distance where the nearest surface point is a
  /// vertex (the point outside), 0 on a face.
  double curvature = 0.0;
};

class RigidBody {
 public:
  /// A convex polygon, vertices in either orientation; part k is edge k (from vertex k to k+1).
  /// Throws InvalidValue for fewer than three vertices, non-finite ones or a non-convex or
  /// degenerate polygon.
  static RigidBody polygon(std::vector<Vec2> vertices);
  /// An axisymmetric pile of `radius` on the axis with its tip (the apex of a conical tip, the
  /// face of a flat one) at height `tip_y`. `apex_angle` [rad] in (0, π): conical tip with this
  /// full apex angle; π: flat tip. Parts: 0 "tip", 1 "shaft", 2 "head" (the far top face).
  static RigidBody pile(double radius, double tip_y, double apex_angle, double length = 1.0e3);

  /// Signed distance, outward normal and part at x (exact distance outside; inside, the
  /// nearest edge's line).
  SurfaceQuery query(const Vec2& x) const;
  double signed_distance(const Vec2& x) const { return query(x).distance; }

  int part_count() const { return static_cast<int>(part_names_.size()); }
  const std::vector<std::string>& part_names() const { return part_names_; }
  bool axisymmetric() const { return axisymmetric_; }
  const std::vector<Vec2>& vertices() const { return vertices_; }  ///< counter-clockwise
  /// Smallest axis-aligned box holding the body (the mirrored section for a pile).
  Vec2 box_min() const;
  Vec2 box_max() const;

  const Vec2& velocity() const { return velocity_; }
  /// Constant over a step, changeable between steps. A pile moves along the axis only: throws
  /// InvalidValue for a radial velocity.
  void set_velocity(const Vec2& velocity);
  /// Coulomb friction coefficient μ = tan δ (>= 0) between the body and the soil.
  double friction() const { return friction_; }
  void set_friction(double friction);
  /// Nodes closer than this to the surface (or inside) are checked for contact [m]; 0: half the
  /// grid's smallest spacing (chosen by the solver).
  double contact_distance() const { return contact_distance_; }
  void set_contact_distance(double distance);
  /// Moves the body by `displacement` [m] (the solver does this by v Δt after each step).
  void translate(const Vec2& displacement);
  /// The sum of all translations since the body was made [m].
  const Vec2& displacement() const { return displacement_; }
  /// Puts the body back where a checkpoint found it: its vertices (as vertices() returned them)
  /// and its displacement. Throws InvalidValue for a different number of vertices.
  void restore_position(const std::vector<Vec2>& vertices, const Vec2& displacement);

 private:
  RigidBody() = default;
  std::vector<Vec2> vertices_;  // counter-clockwise
  std::vector<Vec2> normals_;   // unit outward normal of edge k
  std::vector<int> edge_part_;
  std::vector<std::string> part_names_;
  bool axisymmetric_ = false;
  Vec2 velocity_ = Vec2::Zero();
  double friction_ = 0.0;
  double contact_distance_ = 0.0;
  Vec2 displacement_ = Vec2::Zero();
};

/// The particles whose centre lies inside none of the bodies (bodies wished in place: no
/// particle starts inside one), in their order.
Particles particles_outside(const Particles& particles, const std::vector<RigidBody>& bodies);

}  // namespace pilempm::mpm
