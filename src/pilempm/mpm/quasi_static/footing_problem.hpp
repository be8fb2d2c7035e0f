#pragma once
// Prandtl's strip for the quasi-static analysis (docs/verification.md §9.1): a rigid flat footing
// of width B pushed into a weightless layer of Tresca soil (Mohr-Coulomb with φ = ψ = 0,
// cohesion c), plane strain, half model. The symmetry plane x = 0 and the far side are rollers,
// the base is fixed; cells of (B/2) / `cells_under_footing`, 2 x 2 particles per cell. Prandtl
// (1920): the collapse pressure of a strip on a weightless Tresca half-space is (2 + π) c, for a
// smooth and for a rough footing alike.
#include "pilempm/mpm/quasi_static/quasi_static_solver.hpp"

namespace pilempm::mpm::quasi_static {

struct StripFootingProblem {
  double half_width = 0.5;  ///< B/2 [m]
  double soil_width = 1.5;  ///< of the half model [m]
  double depth = 1.0;       ///< of the layer [m]
  int cells_under_footing = 8;
  double cohesion = 10.0e3;       ///< c [Pa]
  double young_modulus = 10.0e6;  ///< E [Pa]
  double poisson_ratio = 0.3;
  double density = 2000.0;  ///< [kg/m^3] (the soil is weightless: gravity multiplier 0)
  double friction = 0.0;    ///< footing-soil μ (0: smooth)
  /// Geometry is set to plane strain. Defaults: volumetric averaging (B-bar) on, against the
  /// locking of the isochoric plastic flow, a Newton step limit of 0.05 cells and the footing's
  /// edges rounded by a quarter cell.
  Settings settings = default_settings();

  static Settings default_settings();

  /// The solver with the footing (body 0), its base resting on the soil's surface.
  QuasiStaticSolver build() const;
  double cell() const { return half_width / cells_under_footing; }
  /// Prandtl's collapse pressure (2 + π) c [Pa].
  double prandtl_pressure() const;
};

}  // namespace pilempm::mpm::quasi_static
