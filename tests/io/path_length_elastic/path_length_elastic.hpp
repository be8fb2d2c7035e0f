#pragma once
// A model for the tests of the model registry only (not part of the program): isotropic linear
// elasticity that also keeps one history variable, the length of its strain path
// l = sum ||Δε|| (Mandel norm). Everything a model needs to be offered in case files, run in
// element tests and MPM and stored in checkpoints is in this folder; one register_model() line
// in a test adds it to the registry.
#include "pilempm/constitutive/model_registry.hpp"

namespace pilempm::testing {

struct PathLengthElasticParameters {
  double shear_modulus = 0.0;  ///< G [Pa]
  double bulk_modulus = 0.0;   ///< K [Pa]
};

class PathLengthElastic final : public ConstitutiveModel {
 public:
  explicit PathLengthElastic(const PathLengthElasticParameters& parameters);
  std::string name() const override { return "path-length-elastic"; }
  UpdateResult update(MaterialState& state, const Vec6& strain_increment) const override;
  Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const override;
  double wave_modulus(const MaterialState& state) const override;
  std::span<const HistoryVariable> history_variables() const override;

  /// The length of the strain path so far [-].
  static double path_length(const MaterialState& state) { return state.history[0]; }

 private:
  PathLengthElasticParameters parameters_;
};

/// Its registry entry: model = "path-length-elastic", keys shear_modulus_MPa, bulk_modulus_MPa.
ModelRegistration path_length_elastic_registration();

}  // namespace pilempm::testing
