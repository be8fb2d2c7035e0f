#include "path_length_elastic.hpp"

namespace pilempm::testing {

namespace {

constexpr double kMPa = 1.0e6;
constexpr HistoryVariable kHistory[] = {{"path_length", 0, 1, false}};

}  // namespace

PathLengthElastic::PathLengthElastic(const PathLengthElasticParameters& parameters)
    : parameters_(parameters) {}

UpdateResult PathLengthElastic::update(MaterialState& state, const Vec6& strain_increment) const {
  if (!strain_increment.allFinite()) {
    UpdateResult failed;
    failed.ok = false;
    failed.message = "path-length elastic: non-finite strain increment";
    return failed;
  }
  state.stress += tangent(state, strain_increment) * strain_increment;
  state.void_ratio += (1.0 + state.void_ratio) * trace(strain_increment);
  state.history[0] += strain_increment.norm();
  UpdateResult result;
  result.substeps = 1;
  return result;
}

Mat6 PathLengthElastic::tangent(const MaterialState&, const Vec6&) const {
  const Vec6 one = identity6();
  const Mat6 volumetric = outer(one, one) / 3.0;
  return 3.0 * parameters_.bulk_modulus * volumetric +
         2.0 * parameters_.shear_modulus * (Mat6::Identity() - volumetric);
}

double PathLengthElastic::wave_modulus(const MaterialState&) const {
  return parameters_.bulk_modulus + 4.0 / 3.0 * parameters_.shear_modulus;
}

std::span<const HistoryVariable> PathLengthElastic::history_variables() const {
  return kHistory;
}

ModelRegistration path_length_elastic_registration() {
  return make_model_registration<PathLengthElasticParameters>(
      "path-length-elastic", {"shear_modulus_MPa", "bulk_modulus_MPa"},
      [](ParameterSource& source) {
        PathLengthElasticParameters p;
        p.shear_modulus = source.number("shear_modulus_MPa", NumberRange::positive()) * kMPa;
        p.bulk_modulus = source.number("bulk_modulus_MPa", NumberRange::positive()) * kMPa;
        return p;
      },
      [](const PathLengthElasticParameters& p, const IntegratorSettings&) -> ModelPtr {
        return std::make_shared<PathLengthElastic>(p);
      },
      [](const PathLengthElasticParameters& p, const IntegratorSettings&, ParameterSink& out) {
        out.number("shear_modulus_MPa", p.shear_modulus / kMPa);
        out.number("bulk_modulus_MPa", p.bulk_modulus / kMPa);
      },
      [](const PathLengthElasticParameters& p) {  // oedometric: (3K - 2G) / (3K + 4G)
        return (3.0 * p.bulk_modulus - 2.0 * p.shear_modulus) /
               (3.0 * p.bulk_modulus + 4.0 * p.shear_modulus);
      });
}

}  // namespace pilempm::testing
