// Linear elasticity as a [[material]]: its reader, description and registration (see
// model_registry.hpp).
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/constitutive/model_registry.hpp"

namespace pilempm {

namespace {

constexpr double kMPa = 1.0e6;

ElasticParameters read(ParameterSource& t) {
  ElasticParameters p;
  p.young_modulus = t.number("young_modulus_MPa", NumberRange::positive()) * kMPa;
  p.poisson_ratio = t.number("poisson_ratio", NumberRange::open(-1.0, 0.5));
  try {
    p.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e, {{"young_modulus_Pa", "young_modulus_MPa"}});
  }
  return p;
}

}  // namespace

ModelRegistration linear_elastic_registration() {
  return with_parameter_writer<ElasticParameters>(
      make_model_registration<ElasticParameters>(
          "linear-elastic", {"young_modulus_MPa", "poisson_ratio"}, read,
          [](const ElasticParameters& p, const IntegratorSettings&) -> ModelPtr {
            return std::make_shared<LinearElastic>(p);
          },
          [](const ElasticParameters& p, const IntegratorSettings&, ParameterSink& out) {
            out.number("young_modulus_MPa", p.young_modulus / kMPa);
            out.number("poisson_ratio", p.poisson_ratio);
          },
          [](const ElasticParameters& p) {  // oedometric ν / (1 - ν)
            return p.poisson_ratio / (1.0 - p.poisson_ratio);
          }),
      [](const ElasticParameters& p, ParameterSink& out) {
        out.scaled_number("young_modulus_MPa", p.young_modulus, kMPa);
        out.number("poisson_ratio", p.poisson_ratio);
      });
}

}  // namespace pilempm
