// A rigid body's surface with rounded vertices, as the quasi-static contact queries it (internal
// to the quasi-static solver).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "pilempm/mpm/rigid_body.hpp"

namespace pilempm::mpm::quasi_static::detail {

// A rigid body's surface with its vertices rounded by a radius ρ: the points within ρ of the
// inner polygon Q, whose edges are the body's edges moved inward by ρ. The gap is d_Q − ρ, d_Q
// the signed distance to Q, and the normal that of d_Q. On the faces this is the body's own
// surface; at a vertex the normal turns continuously over an arc of radius ρ, also for points
// that have penetrated (up to ρ). The sharp polygon's normal inside the body jumps at the
// bisector of each vertex (by 30° at the pile's shoulder, 90° at a footing's edge), so that a
// penetrated contact point passing a vertex changes its force's direction at once and the Newton
// iterations chatter (docs/quasi-static.md).
struct RoundedSurface {
  double radius = 0.0;    // ρ (declared before Q, which is built from it)
  RigidBody inner;        // Q, a polygon (for a pile: its mirrored section, queried at |r|)
  std::vector<int> part;  // the body's surface part of Q's edge k
  bool axisymmetric = false;

  // `rounding` is cut to what the body admits (below).
  RoundedSurface(const RigidBody& body, double rounding)
      : radius(admissible(body, rounding)),
        inner(RigidBody::polygon(inner_vertices(body, radius))),
        axisymmetric(body.axisymmetric()) {
    const std::vector<Vec2>& v = body.vertices();
    for (std::size_t k = 0; k < v.size(); ++k) {
      // The part of the edge, as the body reports it just outside the edge's middle.
      const Vec2 edge = v[(k + 1) % v.size()] - v[k];
      const Vec2 normal = Vec2(edge.y(), -edge.x()).normalized();
      part.push_back(body.query(v[k] + 0.5 * edge + 1.0e-9 * edge.norm() * normal).part);
    }
  }

  // The largest radius below `rounding` for which every edge of Q keeps 10 % or more of the
  // length it would have at ρ = 0 along its own direction (a thin plate rounded by more than half
  // its thickness would turn Q inside out): Q's edge k is e_k − ρ (m_(k+1) − m_k), m the mitre
  // offsets of inner_vertices.
  static double admissible(const RigidBody& body, double rounding) {
    const std::vector<Vec2>& v = body.vertices();
    const std::size_t count = v.size();
    const std::vector<Vec2> unit = inner_vertices(body, 1.0);  // v − m
    double radius = rounding;
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t next = (k + 1) % count;
      const Vec2 edge = v[next] - v[k];
      const double length = edge.norm();
      const double shrink = ((v[next] - unit[next]) - (v[k] - unit[k])).dot(edge / length);
      if (shrink > 0.0) radius = std::min(radius, 0.9 * length / shrink);
    }
    return std::max(radius, 0.0);
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
    result.distance -= radius;  // the curvature stays Q's, 1/d_Q: the normal is Q's
    result.part = part[std::size_t(result.part)];
    if (axisymmetric && point.x() < 0.0) result.normal.x() = -result.normal.x();
    return result;
  }
};

}  // namespace pilempm::mpm::quasi_static::detail
