#pragma once
// A small axisymmetric pile-jacking problem for the quasi-static analysis: its verification
// (tests/mpm) and its benchmark (bench/bench_quasi_static.cpp). A rigid pile of diameter D with a
// 60° conical tip stands with its tip on (or `embedment_in_d` D below) the surface of a sand
// cylinder (radius `width_in_d` D, height `height_in_d` D) at N g, from a K0 stress state; cells of
// D / `cells_per_d` (uniform), 2 x 2 particles per cell, rollers on the outer side and the axis,
// fixed base. A hypoplastic sand with intergranular strain starts with it fully mobilised by
// isotropic compression (−R/√3 I), as the case files' default.
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

namespace pilempm::mpm::quasi_static {

struct PileProblem {
  double diameter = 0.02;    ///< D [m]
  double width_in_d = 5.0;   ///< radius of the sand / D
  double height_in_d = 8.0;  ///< height of the sand / D
  int cells_per_d = 4;       ///< cells across D
  double gravity_multiplier = 50.0;
  double density = 1600.0;      ///< [kg/m^3]
  double earth_pressure = 0.5;  ///< K0
  double void_ratio = 0.7;
  double friction = 0.3;  ///< pile-sand μ
  /// Depth of the tip below the surface at the start / D (0: on the surface). An embedded pile is
  /// wished in place: no particle starts with its centre inside it.
  double embedment_in_d = 0.0;
  ModelPtr model;  ///< the sand
  /// Geometry is set to axisymmetric. Default: a Newton step limit of 0.1 cells (without it the
  /// Mohr-Coulomb push fails at 1.75 D, docs/quasi-static.md).
  Settings settings = default_settings();

  static Settings default_settings();

  /// The solver with the pile (body 0) and the sand in its K0 state (gravity multiplier N
  /// already reached: the first load step is the geostatic equilibrium).
  QuasiStaticSolver build() const;
  /// The initial height of the sand's surface [m].
  double surface() const { return height_in_d * diameter; }
};

/// The sands of the pile verification (docs/verification.md §9.2). Mohr-Coulomb: E = 50 MPa,
/// ν = 0.3, φ = 35°, ψ = 5°, c = 1 kPa.
ModelPtr pile_mohr_coulomb_sand();
/// Hypoplasticity with intergranular strain, the study's set `modified-medium-dense` with `IGS3`
/// (docs/model.md §6; its e0 is 0.68).
ModelPtr pile_hypoplastic_sand();

}  // namespace pilempm::mpm::quasi_static
