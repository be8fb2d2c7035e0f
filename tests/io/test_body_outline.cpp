// The rigid bodies as drawn (ParaView's bodies_NNNNN.vtu, the field figures' pile): the body's
// own vertices where it lies below the cut, the cut's points on its edges.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "pilempm/io/mpm_output.hpp"
#include "pilempm/mpm/rigid_body.hpp"

namespace pilempm {
namespace {

using mpm::Vec2;

bool holds(const std::vector<Vec2>& points, const Vec2& p) {
  for (const Vec2& q : points)
    if ((q - p).norm() < 1e-12) return true;
  return false;
}

// Twice the signed area (shoelace): > 0 counter-clockwise.
double twice_area(const std::vector<Vec2>& polygon) {
  double sum = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vec2& a = polygon[k];
    const Vec2& b = polygon[(k + 1) % polygon.size()];
    sum += a.x() * b.y() - b.x() * a.y();
  }
  return sum;
}

TEST(BodyOutline, APileIsCutAtTheTopAndFollowsItsDisplacement) {
  const double R = 0.01, tip = 0.2;
  mpm::RigidBody pile = mpm::RigidBody::pile(R, tip, std::numbers::pi / 3.0, 10.0);
  pile.translate(Vec2(0.0, -0.05));
  const double top = 0.4;
  const std::vector<Vec2> full = mpm_body_outline(pile, top);
  // The tip and both shoulders where the body is now; the shaft cut at the top.
  ASSERT_EQ(full.size(), 5u);
  for (const Vec2& v : pile.vertices()) {
    if (v.y() <= top) {
      EXPECT_TRUE(holds(full, v)) << v.transpose();
    }
  }
  EXPECT_TRUE(holds(full, Vec2(0.0, tip - 0.05)));
  EXPECT_TRUE(holds(full, Vec2(R, top)));
  EXPECT_TRUE(holds(full, Vec2(-R, top)));
  EXPECT_GT(twice_area(full), 0.0);
  // The section's area: a 2R-wide shaft from the shoulders to the top plus the cone's triangle.
  const double cone = R / std::tan(std::numbers::pi / 6.0);
  const double shoulder = tip - 0.05 + cone;
  EXPECT_NEAR(0.5 * twice_area(full), 2.0 * R * (top - shoulder) + R * cone, 1e-15);

  // The half-section r >= 0: the axis from the tip to the top.
  const std::vector<Vec2> half = mpm_body_outline(pile, top, true);
  ASSERT_EQ(half.size(), 4u);
  for (const Vec2& v : half) EXPECT_GE(v.x(), 0.0);
  EXPECT_TRUE(holds(half, Vec2(0.0, tip - 0.05)));
  EXPECT_TRUE(holds(half, Vec2(R, shoulder)));
  EXPECT_TRUE(holds(half, Vec2(R, top)));
  EXPECT_TRUE(holds(half, Vec2(0.0, top)));
  EXPECT_NEAR(2.0 * twice_area(half), twice_area(full), 1e-15);

  // A body wholly above the cut is not drawn.
  EXPECT_TRUE(mpm_body_outline(pile, tip - 0.1).empty());
}

TEST(BodyOutline, APolygonBelowTheCutIsItsVertices) {
  mpm::RigidBody plate = mpm::RigidBody::polygon({{0.3, 0.5}, {0.7, 0.5}, {0.7, 0.6}, {0.3, 0.6}});
  plate.translate(Vec2(0.01, -0.02));
  EXPECT_EQ(mpm_body_outline(plate, 1.0), plate.vertices());
}

}  // namespace
}  // namespace pilempm
