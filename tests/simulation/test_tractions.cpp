// Surface tractions as particle forces: only the outermost row of the region's side is loaded,
// and the forces add up to the traction times the side's length (per metre) or times ∫ r dr
// over it (per radian, axisymmetry).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/simulation/tractions.hpp"

namespace pilempm {
namespace {

using namespace simulation;

// Region 1: [0.2, 0.8] × [0.1, 0.5] on a uniform grid of 0.1 m, 2 × 3 particles per
// cell; region 0: a layer below it that must not be loaded.
mpm::Particles two_regions(mpm::Geometry geometry) {
  const mpm::Grid grid(mpm::GridAxis::uniform(0.0, 1.0, 10), mpm::GridAxis::uniform(0.0, 1.0, 10));
  mpm::Particles particles;
  mpm::RectangleFill below;
  below.x_min = 0.0, below.x_max = 1.0, below.y_min = 0.0, below.y_max = 0.1;
  below.density = 1000.0;
  below.material = 0;
  mpm::fill_rectangle(particles, grid, geometry, below);
  mpm::RectangleFill block;
  block.x_min = 0.2, block.x_max = 0.8, block.y_min = 0.1, block.y_max = 0.5;
  block.particles_per_cell_x = 2;
  block.particles_per_cell_y = 3;
  block.density = 1000.0;
  block.material = 1;
  mpm::fill_rectangle(particles, grid, geometry, block);
  return particles;
}

struct Sums {
  mpm::Vec2 force = mpm::Vec2::Zero();
  int loaded = 0;
};

Sums sum(const mpm::Particles& particles, const std::vector<mpm::Vec2>& forces) {
  Sums s;
  EXPECT_EQ(forces.size(), particles.size());
  for (std::size_t p = 0; p < forces.size(); ++p) {
    if (forces[p] == mpm::Vec2::Zero()) continue;
    EXPECT_EQ(particles.material[p], 1) << p;
    s.force += forces[p];
    ++s.loaded;
  }
  return s;
}

TEST(MpmTractions, PlaneStrainForcesAddUpToTractionTimesSideLength) {
  const mpm::Particles particles = two_regions(mpm::Geometry::plane_strain);
  // Top: 100 kPa pushing down, 10 kPa shear along +x on 0.6 m; 12 particles in the top row.
  Sums top = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::plane_strain,
                                                 mpm::Side::top, 100e3, 10e3));
  EXPECT_EQ(top.loaded, 12);
  EXPECT_NEAR(top.force.y(), -100e3 * 0.6, 1e-6);
  EXPECT_NEAR(top.force.x(), 10e3 * 0.6, 1e-6);
  // Bottom: pushing up into the region.
  Sums bottom = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::plane_strain,
                                                    mpm::Side::bottom, 50e3, 0.0));
  EXPECT_EQ(bottom.loaded, 12);
  EXPECT_NEAR(bottom.force.y(), 50e3 * 0.6, 1e-6);
  // Left: pushing along +x on 0.4 m, shear along +y; 12 particles in the left column.
  Sums left = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::plane_strain,
                                                  mpm::Side::left, 20e3, -5e3));
  EXPECT_EQ(left.loaded, 12);
  EXPECT_NEAR(left.force.x(), 20e3 * 0.4, 1e-6);
  EXPECT_NEAR(left.force.y(), -5e3 * 0.4, 1e-6);
  Sums right = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::plane_strain,
                                                   mpm::Side::right, 20e3, 0.0));
  EXPECT_NEAR(right.force.x(), -20e3 * 0.4, 1e-6);
}

TEST(MpmTractions, AxisymmetricForcesArePerRadian) {
  const mpm::Particles particles = two_regions(mpm::Geometry::axisymmetric);
  // Top: ∫ r dr from 0.2 to 0.8 = (0.64 - 0.04) / 2 = 0.3 m^2 per radian.
  Sums top = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::axisymmetric,
                                                 mpm::Side::top, 100e3, 0.0));
  EXPECT_EQ(top.loaded, 12);
  EXPECT_NEAR(top.force.y(), -100e3 * 0.3, 1e-6);
  EXPECT_NEAR(top.force.x(), 0.0, 1e-9);
  // Right side at r = 0.8 over 0.4 m: 0.32 m^2 per radian; left at r = 0.2: 0.08.
  Sums right = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::axisymmetric,
                                                   mpm::Side::right, 100e3, 0.0));
  EXPECT_NEAR(right.force.x(), -100e3 * 0.32, 1e-6);
  Sums left = sum(particles, side_traction_forces(particles, 1, mpm::Geometry::axisymmetric,
                                                  mpm::Side::left, 100e3, 0.0));
  EXPECT_NEAR(left.force.x(), 100e3 * 0.08, 1e-6);
}

TEST(MpmTractions, CaseTractionsAddUpAndNoRegionMeansNoForce) {
  MpmCase c;
  c.geometry = mpm::Geometry::plane_strain;
  c.tractions.push_back({0, "traction[0]", 1, mpm::Side::top, 100e3, 0.0});
  c.tractions.push_back({0, "traction[1]", 1, mpm::Side::top, 50e3, 0.0});
  const mpm::Particles particles = two_regions(c.geometry);
  Sums total = sum(particles, mpm_traction_forces(c, particles));
  EXPECT_NEAR(total.force.y(), -150e3 * 0.6, 1e-6);
  Sums none =
      sum(particles, side_traction_forces(particles, 7, c.geometry, mpm::Side::top, 100e3, 0.0));
  EXPECT_EQ(none.loaded, 0);
}

}  // namespace
}  // namespace pilempm
