// Surface tractions as particle forces: see tractions.hpp.
#include "pilempm/simulation/tractions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pilempm::simulation {

std::vector<mpm::Vec2> side_traction_forces(const mpm::Particles& particles, int material,
                                            mpm::Geometry geometry, mpm::Side side, double normal,
                                            double shear) {
  const std::size_t n = particles.size();
  std::vector<mpm::Vec2> forces(n, mpm::Vec2::Zero());
  // The side's axis (0: x for left/right, 1: y for bottom/top), its outward sense, and the
  // direction of the particles' edge along it.
  const bool vertical_side = side == mpm::Side::left || side == mpm::Side::right;
  const Eigen::Index normal_axis = vertical_side ? 0 : 1;
  const Eigen::Index edge_axis = 1 - normal_axis;
  const double outward = side == mpm::Side::right || side == mpm::Side::top ? 1.0 : -1.0;

  // The outermost extent of the particles' domains on that side.
  double extreme = -std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p)
    if (particles.material[p] == material)
      extreme = std::max(extreme, outward * particles.position[p][normal_axis] +
                                      particles.initial_half_size[p][normal_axis]);
  if (!std::isfinite(extreme)) return forces;

  mpm::Vec2 traction = mpm::Vec2::Zero();
  traction[normal_axis] = -outward * normal;  // pushing into the region
  traction[edge_axis] = shear;
  for (std::size_t p = 0; p < n; ++p) {
    if (particles.material[p] != material) continue;
    const mpm::Vec2& x = particles.position[p];
    const mpm::Vec2& h = particles.initial_half_size[p];
    // The outermost row: its domain reaches the extreme (the next row in ends 2 h further in).
    if (outward * x[normal_axis] + h[normal_axis] < extreme - 0.5 * h[normal_axis]) continue;
    double share = 2.0 * h[edge_axis];
    if (geometry == mpm::Geometry::axisymmetric)
      share *= vertical_side ? x.x() + outward * h.x() : x.x();  // ∫ r dr over the edge
    forces[p] = share * traction;
  }
  return forces;
}

std::vector<mpm::Vec2> mpm_traction_forces(const MpmCase& c, const mpm::Particles& particles) {
  std::vector<mpm::Vec2> total(particles.size(), mpm::Vec2::Zero());
  for (const MpmTraction& t : c.tractions) {
    const std::vector<mpm::Vec2> forces =
        side_traction_forces(particles, t.region, c.geometry, t.side, t.normal, t.shear);
    for (std::size_t p = 0; p < total.size(); ++p) total[p] += forces[p];
  }
  return total;
}

}  // namespace pilempm::simulation
