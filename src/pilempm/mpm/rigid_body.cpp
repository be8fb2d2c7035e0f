#include "pilempm/mpm/rigid_body.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "pilempm/core/error.hpp"

namespace pilempm::mpm {

namespace {

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

RigidBody RigidBody::polygon(std::vector<Vec2> vertices) {
  const std::size_t count = vertices.size();
  if (count < 3) throw InvalidValue("rigid polygon vertices", std::to_string(count), "at least 3");
  for (const Vec2& v : vertices)
    if (!v.allFinite()) throw InvalidValue("rigid polygon vertex", "not finite", "finite");
  double area = 0.0;  // twice the signed area (shoelace)
  for (std::size_t k = 0; k < count; ++k) area += cross(vertices[k], vertices[(k + 1) % count]);
  if (area < 0.0) std::reverse(vertices.begin(), vertices.end());
  RigidBody body;
  for (std::size_t k = 0; k < count; ++k) {
    const Vec2 edge = vertices[(k + 1) % count] - vertices[k];
    const Vec2 next = vertices[(k + 2) % count] - vertices[(k + 1) % count];
    if (!(edge.norm() > 0.0) || !(cross(edge, next) > 0.0))
      throw InvalidValue("rigid polygon", fmt::format("corner at vertex {}", (k + 1) % count),
                         "convex, without repeated or collinear vertices");
    body.normals_.push_back(Vec2(edge.y(), -edge.x()).normalized());
    body.edge_part_.push_back(static_cast<int>(k));
    body.part_names_.push_back(fmt::format("edge {}", k));
  }
  body.vertices_ = std::move(vertices);
  return body;
}

RigidBody RigidBody::pile(double radius, double tip_y, double apex_angle, double length) {
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw InvalidValue("pile radius", format_value(radius), "> 0");
  if (!std::isfinite(tip_y)) throw InvalidValue("pile tip", format_value(tip_y), "finite");
  if (!(apex_angle > 0.0 && apex_angle <= std::numbers::pi))
    throw InvalidValue("pile apex angle", format_value(apex_angle), "in (0, π] (π: flat tip)");
  const bool flat = apex_angle >= std::numbers::pi;
  const double cone_height = flat ? 0.0 : radius / std::tan(0.5 * apex_angle);
  if (!(length > cone_height && std::isfinite(length)))
    throw InvalidValue("pile length", format_value(length), "longer than the tip");
  const double shoulder = tip_y + cone_height, top = tip_y + length;
  // The half-section mirrored about the axis, counter-clockwise from the tip.
  std::vector<Vec2> vertices;
  std::vector<int> parts;
  if (flat) {
    vertices = {{-radius, tip_y}, {radius, tip_y}, {radius, top}, {-radius, top}};
    parts = {0, 1, 2, 1};
  } else {
    vertices = {
        {0.0, tip_y}, {radius, shoulder}, {radius, top}, {-radius, top}, {-radius, shoulder}};
    parts = {0, 1, 2, 1, 0};
  }
  RigidBody body = polygon(std::move(vertices));
  body.edge_part_ = std::move(parts);
  body.part_names_ = {"tip", "shaft", "head"};
  body.axisymmetric_ = true;
  return body;
}

SurfaceQuery RigidBody::query(const Vec2& point) const {
  const Vec2 x = axisymmetric_ ? Vec2(std::abs(point.x()), point.y()) : point;
  const std::size_t count = vertices_.size();
  // Inside a convex polygon the distance is the largest of the edge lines' signed distances.
  double largest = -std::numeric_limits<double>::infinity();
  std::size_t largest_edge = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double s = normals_[k].dot(x - vertices_[k]);
    if (s > largest) {
      largest = s;
      largest_edge = k;
    }
  }
  SurfaceQuery result;
  if (largest <= 0.0) {
    result.distance = largest;
    result.normal = normals_[largest_edge];
    result.part = edge_part_[largest_edge];
  } else {  // outside: the nearest point on the edges
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < count; ++k) {
      const Vec2& a = vertices_[k];
      const Vec2 edge = vertices_[(k + 1) % count] - a;
      const double t = std::clamp((x - a).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
      const Vec2 offset = x - (a + t * edge);
      const double distance = offset.norm();
      if (distance < nearest) {
        nearest = distance;
        result.distance = distance;
        result.normal = distance > 0.0 ? Vec2(offset / distance) : normals_[k];
        result.part = edge_part_[k];
        const bool at_vertex = !(t > 0.0 && t < 1.0);
        result.curvature = at_vertex && distance > 0.0 ? 1.0 / distance : 0.0;
      }
    }
  }
  if (axisymmetric_ && point.x() < 0.0) result.normal.x() = -result.normal.x();
  return result;
}

Vec2 RigidBody::box_min() const {
  Vec2 low = vertices_.front();
  for (const Vec2& v : vertices_) low = low.cwiseMin(v);
  return low;
}

Vec2 RigidBody::box_max() const {
  Vec2 high = vertices_.front();
  for (const Vec2& v : vertices_) high = high.cwiseMax(v);
  return high;
}

void RigidBody::set_velocity(const Vec2& velocity) {
  if (!velocity.allFinite()) throw InvalidValue("rigid body velocity", "not finite", "finite");
  if (axisymmetric_ && velocity.x() != 0.0)
    throw InvalidValue("pile radial velocity", format_value(velocity.x()), "0 (along the axis)");
  velocity_ = velocity;
}

void RigidBody::set_friction(double friction) {
  if (!(friction >= 0.0 && std::isfinite(friction)))
    throw InvalidValue("rigid body friction coefficient", format_value(friction), ">= 0");
  friction_ = friction;
}

void RigidBody::set_contact_distance(double distance) {
  if (!(distance >= 0.0 && std::isfinite(distance)))
    throw InvalidValue("rigid body contact distance", format_value(distance),
                       ">= 0 (0: half the smallest cell)");
  contact_distance_ = distance;
}

void RigidBody::translate(const Vec2& displacement) {
  for (Vec2& v : vertices_) v += displacement;
  displacement_ += displacement;
}

void RigidBody::restore_position(const std::vector<Vec2>& vertices, const Vec2& displacement) {
  if (vertices.size() != vertices_.size())
    throw InvalidValue("rigid body vertex count", std::to_string(vertices.size()),
                       std::to_string(vertices_.size()) + " (the body's own)");
  vertices_ = vertices;
  displacement_ = displacement;
}

Particles particles_outside(const Particles& particles, const std::vector<RigidBody>& bodies) {
  Particles outside;
  outside.reserve(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const Vec2& x = particles.position[p];
    if (std::any_of(bodies.begin(), bodies.end(),
                    [&](const RigidBody& b) { return b.signed_distance(x) < 0.0; }))
      continue;
    outside.add({x, particles.velocity[p], particles.mass[p], particles.initial_volume[p],
                 particles.initial_half_size[p], particles.material[p], particles.state[p]});
  }
  return outside;
}

}  // namespace pilempm::mpm
