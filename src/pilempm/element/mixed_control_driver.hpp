#pragma once
// A single material point driven by mixed control: in every increment each of the six Mandel
// components is either strain-controlled (its strain increment is given) or stress-controlled
// (its stress at the end of the increment is given, the strain increment is solved for).
#include <array>

#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm {

/// What one increment prescribes.
struct MixedIncrement {
  std::array<bool, 6> stress_controlled{};  ///< per Mandel component
  Vec6 strain_increment = Vec6::Zero();     ///< used for the strain-controlled components
  Vec6 stress_target = Vec6::Zero();        ///< used for the stress-controlled components [Pa]
};

/// Settings of the equilibrium iteration for the stress-controlled components.
// The equilibrium iteration aims at `relative_tolerance`. The model's adaptive integrator makes its
// stress a piecewise smooth function of the strain increment (the sub-step pattern changes with
// it), with jumps of the order of the integrator's own error; where the iteration stalls on such
// a jump, a residual below `acceptable_relative_tolerance` is accepted.
struct MixedControlSettings {
  double stress_tolerance = 1.0e-3;               ///< absolute [Pa]
  double relative_tolerance = 1.0e-10;            ///< aim, relative to the largest stress
  double acceptable_relative_tolerance = 1.0e-5;  ///< accepted when the iteration stalls
  int max_iterations = 60;
};

/// Drives one point. Throws pilempm::Error when the model fails or the iteration diverges, with
/// the increment number in the message; the point keeps its last converged state.
class MixedControlDriver {
 public:
  MixedControlDriver(const ConstitutiveModel& model, const MaterialState& initial,
                     MixedControlSettings settings = {});

  /// Applies one increment and returns the model's report of the accepted update.
  UpdateResult apply(const MixedIncrement& increment);

  const MaterialState& state() const { return state_; }
  /// Accumulated strain (sum of the increments: logarithmic strain on coaxial paths).
  const Vec6& strain() const { return strain_; }
  /// The strain increment of the last applied increment.
  const Vec6& last_strain_increment() const { return last_increment_; }
  long increments() const { return count_; }
  const ConstitutiveModel& model() const { return model_; }

 private:
  const ConstitutiveModel& model_;
  MaterialState state_;
  MixedControlSettings settings_;
  Vec6 strain_ = Vec6::Zero();
  Vec6 last_increment_ = Vec6::Zero();
  std::array<bool, 6> last_control_{};
  long count_ = 0;
};

}  // namespace pilempm
