#pragma once
// Surface tractions of MPM case files ([[traction]], docs/mpm-case-files.md) as dead-load point
// forces on particles: a uniform traction on one side of a rectangular region acts on the
// particles of the region's outermost row (column) on that side, each taking the traction times
// its share of the side, the edge of its sub-cell (2 × its initial half-size). In axisymmetry the
// share is per radian: times ∫ r dr over the edge, which is r_p × edge length on the bottom and
// top sides and r_side × edge length on the left and right sides (r_side: the radius of the side
// itself). The sum of the forces is thus the traction times the side's length (area per radian).
#include <vector>

#include "pilempm/mpm/particles.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm::simulation {

/// The point forces [N] (per metre in plane strain, per radian in axisymmetry) of a traction
/// `normal` [Pa] (positive pushing into the particles) and `shear` [Pa] (positive along +x on the
/// bottom and top sides, along +y on the left and right sides) on side `side` of the particles
/// whose material index is `material`, one entry per particle (zero for the others).
std::vector<mpm::Vec2> side_traction_forces(const mpm::Particles& particles, int material,
                                            mpm::Geometry geometry, mpm::Side side, double normal,
                                            double shear);

/// The sum of the point forces of all [[traction]] tables of a case at multiplier 1, one entry per
/// particle of `particles` as make_mpm_particles made them (region i has material index i).
std::vector<mpm::Vec2> mpm_traction_forces(const MpmCase& mpm_case,
                                           const mpm::Particles& particles);

}  // namespace pilempm::simulation
