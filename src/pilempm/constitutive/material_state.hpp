#pragma once
// The state a constitutive model carries at one material point.
#include <array>

#include "pilempm/core/tensor.hpp"

namespace pilempm {

/// Room for a model's history variables at one point (the largest model's need: a Mandel
/// tensor and a scalar). Raise it for a model that needs more.
inline constexpr int kHistoryCapacity = 7;

/// Everything a model needs to remember at one point. SI units, tension positive. What the
/// history slots hold is the model's to say (ConstitutiveModel::history_variables()).
struct MaterialState {
  Vec6 stress = Vec6::Zero();  ///< Cauchy (effective) stress [Pa], Mandel notation
  double void_ratio = 0.0;     ///< e [-]
  std::array<double, kHistoryCapacity> history{};  ///< the model's history variables
};

/// One history variable of a model: its name (in checkpoints and messages), where it lies in
/// MaterialState::history and whether it is a symmetric tensor in Mandel notation (size 6,
/// rotated with the stress by an objective update) or `size` scalars.
struct HistoryVariable {
  const char* name;
  int offset;
  int size;
  bool tensor;
};

/// Mean stress p = -tr(T)/3 [Pa], compression positive.
inline double mean_stress(const Vec6& stress) {
  return -trace(stress) / 3.0;
}

/// Deviator stress q = sqrt(3/2) ||dev T|| [Pa].
inline double deviator_stress(const Vec6& stress) {
  return std::sqrt(1.5) * deviator(stress).norm();
}

}  // namespace pilempm
