#pragma once
// Typed MPM cases built as the case-file reader builds them, without a file: for the tests of the
// layers below io/. Each builder sets what its name says and the reader's defaults elsewhere.
#include <string>
#include <utility>

#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::test_support {

/// A uniform grid axis: `cells` equal cells from min to max [m].
inline simulation::MpmGridAxis uniform_axis(double min, double max, int cells) {
  simulation::MpmGridAxis axis;
  axis.min = min;
  axis.max = max;
  axis.cells = cells;
  return axis;
}

/// A case with its geometry and a uniform grid, every side free, the solver's defaults.
inline simulation::MpmCase grid_case(std::string title, mpm::Geometry geometry,
                                     const simulation::MpmGridAxis& x,
                                     const simulation::MpmGridAxis& y) {
  simulation::MpmCase c;
  c.source = title + ".toml";
  c.title = std::move(title);
  c.geometry = geometry;
  c.x_axis = x;
  c.y_axis = y;
  c.x_nodes = x.nodes();
  c.y_nodes = y.nodes();
  c.boundaries.fill(mpm::BoundaryCondition::free);
  c.solver.geometry = geometry;
  return c;
}

/// Adds a [[region]] of `material` (a model without intergranular strain), stress free, as the
/// rectangle `fill` (its material index is set to the region's).
inline void add_region(simulation::MpmCase& c, const MaterialSpec& material,
                       mpm::RectangleFill fill) {
  simulation::MpmRegion r;
  const int index = static_cast<int>(c.regions.size());
  r.name = "region" + std::to_string(index + 1);
  r.key = "region[" + std::to_string(index) + "]";
  fill.material = index;
  r.fill = fill;
  r.material = material;
  c.models.push_back(make_model(material, std::nullopt, c.integrator));
  c.material_names.push_back(material.name);
  c.regions.push_back(std::move(r));
}

/// Adds a [[phase]] of `duration` [s] with the solver's N and damping, snapshots every
/// `output_interval` and records every `energy_interval` [s], the bodies at rest.
inline simulation::MpmPhase& add_phase(simulation::MpmCase& c, std::string name, double duration,
                                       double output_interval, double energy_interval) {
  simulation::MpmPhase p;
  p.name = std::move(name);
  p.duration = duration;
  p.gravity_multiplier = c.solver.gravity_multiplier;
  p.local_damping = c.solver.local_damping;
  p.output_interval = output_interval;
  p.energy_interval = energy_interval;
  p.body_motion.assign(c.bodies.size(), simulation::MpmBodyMotion{});
  c.phases.push_back(std::move(p));
  return c.phases.back();
}

}  // namespace pilempm::test_support
