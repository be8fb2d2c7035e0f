// Materials as data: see material_spec.hpp.
#include "pilempm/constitutive/material_spec.hpp"

#include <fmt/format.h>

#include "pilempm/core/error.hpp"

namespace pilempm {

const HypoplasticMaterial& MaterialSpec::hypoplastic_material() const {
  if (const HypoplasticMaterial* m = parameters_as<HypoplasticMaterial>()) return *m;
  throw Error(fmt::format("material \"{}\" is {}, not hypoplastic", name, model));
}

MaterialSpec with_igs(const MaterialSpec& material, const std::optional<IgsChoice>& igs) {
  const HypoplasticMaterial* hypoplastic = material.parameters_as<HypoplasticMaterial>();
  if (hypoplastic == nullptr) return material;
  HypoplasticMaterial changed = *hypoplastic;
  changed.igs = igs;
  MaterialSpec result = material;
  result.parameters = std::make_shared<const ParametersOf<HypoplasticMaterial>>(changed);
  return result;
}

MaterialSpec builtin_material(std::string_view set_name) {
  MaterialSpec m;
  m.name = std::string(set_name);
  m.model = "hypoplastic";
  m.builtin = true;
  m.parameters = std::make_shared<const ParametersOf<HypoplasticMaterial>>(
      HypoplasticMaterial{hypoplastic_set(set_name), "", std::nullopt});
  m.origin = "built-in set";
  return m;
}

ModelPtr make_model(const MaterialSpec& material, const std::optional<IgsChoice>& igs,
                    const IntegratorSettings& integrator) {
  const MaterialSpec effective = with_igs(material, igs);
  return model_registry().at(material.model).make(*effective.parameters, integrator);
}

}  // namespace pilempm
