#pragma once
// The one interface through which every consumer (element tests, MPM, calibration, benchmarks)
// calls a constitutive model. A model knows nothing of grids, particles or files.
#include <memory>
#include <string>

#include "pilempm/constitutive/material_state.hpp"

namespace pilempm {

/// What happened during one stress update. A failed update leaves the state unchanged.
struct UpdateResult {
  bool ok = true;
  int substeps = 0;                ///< accepted sub-steps of the integrator
  int rejected_substeps = 0;       ///< sub-steps rejected by the error control
  int mean_stress_floor_hits = 0;  ///< times the stress was set to the floor p_min (see model doc)
  double void_ratio_excess = 0.0;  ///< largest relative distance e left its band before clamping
  const char* message = "";        ///< why it failed (static text), empty when ok
};

/// A constitutive model: parameters in, and a pure function from (state, strain increment) to the
/// new state. Implementations are immutable after construction and safe to call from many threads.
class ConstitutiveModel {
 public:
  virtual ~ConstitutiveModel() = default;

  /// Short name for messages and output, e.g. "hypoplastic+IGS".
  virtual std::string name() const = 0;

  /// Advances the state by a small-strain increment (Mandel, tension positive). Objective
  /// rotation of the stress by the spin is the caller's job (see objective_rotation.hpp), so the
  /// same code serves the element tests (no spin) and the MPM solver.
  virtual UpdateResult update(MaterialState& state, const Vec6& strain_increment) const = 0;

  /// Tangent d(stress rate)/d(strain rate) at the state for a strain rate in the given direction
  /// (rate-independent models with a direction-dependent tangent need the direction).
  virtual Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const = 0;

  /// Upper bound of the constrained (P-wave) modulus at the state [Pa], for the critical time step.
  virtual double wave_modulus(const MaterialState& state) const = 0;
};

using ModelPtr = std::shared_ptr<const ConstitutiveModel>;

}  // namespace pilempm
