#pragma once
// The state a constitutive model carries at one material point.
#include "pilempm/core/tensor.hpp"

namespace pilempm {

/// Everything a model needs to remember at one point. SI units, tension positive.
struct MaterialState {
  Vec6 stress = Vec6::Zero();                ///< Cauchy (effective) stress [Pa], Mandel notation
  double void_ratio = 0.0;                   ///< e [-]
  Vec6 intergranular_strain = Vec6::Zero();  ///< delta of Niemunis & Herle (1997) [-]
  double plastic_shear_strain = 0.0;         ///< accumulated plastic shear strain (Mohr-Coulomb)
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
