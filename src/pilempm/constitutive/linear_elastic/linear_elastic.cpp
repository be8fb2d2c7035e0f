#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"

#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

void ElasticParameters::validate() const {
  if (!(young_modulus > 0.0 && std::isfinite(young_modulus)))
    throw InvalidValue("young_modulus_Pa", format_value(young_modulus), "> 0");
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw InvalidValue("poisson_ratio", format_value(poisson_ratio), "in (-1, 0.5)");
}

Mat6 ElasticParameters::stiffness() const {
  const Vec6 one = identity6();
  const Mat6 volumetric = outer(one, one) / 3.0;
  const Mat6 deviatoric = Mat6::Identity() - volumetric;
  return 3.0 * bulk_modulus() * volumetric + 2.0 * shear_modulus() * deviatoric;
}

LinearElastic::LinearElastic(const ElasticParameters& parameters)
    : parameters_(parameters),
      stiffness_((parameters.validate(), parameters.stiffness())),
      two_shear_modulus_(2.0 * parameters.shear_modulus()),
      lame_lambda_(parameters.bulk_modulus() - 2.0 / 3.0 * parameters.shear_modulus()) {}

UpdateResult LinearElastic::update(MaterialState& state, const Vec6& strain_increment) const {
  // The new state in temporaries; a non-finite input (or an overflow) leaves a non-finite value
  // there, and 0 x (each value) sums to NaN exactly then: one check instead of one per input.
  const double volumetric = trace(strain_increment);
  Vec6 stress = state.stress + two_shear_modulus_ * strain_increment;
  const double pressure_change = lame_lambda_ * volumetric;
  for (int k = 0; k < 3; ++k) stress[k] += pressure_change;
  const double void_ratio = state.void_ratio + (1.0 + state.void_ratio) * volumetric;
  if (!std::isfinite((0.0 * stress).sum() + 0.0 * void_ratio + 0.0 * state.void_ratio)) {
    UpdateResult failed;
    failed.ok = false;
    failed.message = "linear elastic: non-finite stress, void ratio or strain increment";
    return failed;
  }
  state.stress = stress;
  state.void_ratio = void_ratio;
  UpdateResult result;
  result.substeps = 1;
  return result;
}

Mat6 LinearElastic::tangent(const MaterialState&, const Vec6&) const {
  return stiffness_;
}

bool LinearElastic::consistent_tangent(const MaterialState&, const Vec6&, Mat6& tangent) const {
  tangent = stiffness_;
  return true;
}

double LinearElastic::wave_modulus(const MaterialState&) const {
  return parameters_.bulk_modulus() + 4.0 / 3.0 * parameters_.shear_modulus();
}

}  // namespace pilempm
