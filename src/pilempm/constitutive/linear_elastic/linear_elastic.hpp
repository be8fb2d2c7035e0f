#pragma once
// Isotropic linear elasticity (Hooke), mainly for verification.
#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm {

struct ElasticParameters {
  double young_modulus = 0.0;  ///< E [Pa], > 0
  double poisson_ratio = 0.0;  ///< nu [-], in (-1, 0.5)

  /// Throws InvalidValue naming the first impossible value.
  void validate() const;
  double shear_modulus() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double bulk_modulus() const { return young_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)); }
  /// Isotropic stiffness 3K P_vol + 2G P_dev in Mandel notation.
  Mat6 stiffness() const;
};

class LinearElastic final : public ConstitutiveModel {
 public:
  explicit LinearElastic(const ElasticParameters& parameters);
  std::string name() const override { return "linear-elastic"; }
  UpdateResult update(MaterialState& state, const Vec6& strain_increment) const override;
  Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const override;
  /// Its stiffness: the update is linear.
  bool consistent_tangent(const MaterialState& state, const Vec6& strain_increment,
                          Mat6& tangent) const override;
  double wave_modulus(const MaterialState& state) const override;

 private:
  ElasticParameters parameters_;
  Mat6 stiffness_;
  // The update as 2G Δε + λ tr(Δε) 1 (the product with stiffness_ to round-off, a fifth of the
  // work).
  double two_shear_modulus_;
  double lame_lambda_;
};

}  // namespace pilempm
