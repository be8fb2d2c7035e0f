// Materials as data: see material_spec.hpp.
#include "pilempm/constitutive/material_spec.hpp"

#include <memory>

#include "pilempm/core/error.hpp"

namespace pilempm {

std::string_view to_string(ModelKind kind) {
  switch (kind) {
    case ModelKind::hypoplastic:
      return "hypoplastic";
    case ModelKind::mohr_coulomb:
      return "mohr-coulomb";
    case ModelKind::linear_elastic:
      return "linear-elastic";
  }
  return "?";
}

IgsChoice named_igs(std::string_view name) {
  return {std::string(name), intergranular_strain_set(name)};
}

std::vector<std::string> igs_choice_names() {
  return intergranular_strain_set_names();
}

MaterialSpec builtin_material(std::string_view set_name) {
  MaterialSpec m;
  m.name = std::string(set_name);
  m.kind = ModelKind::hypoplastic;
  m.builtin = true;
  m.hypoplastic = hypoplastic_set(set_name);
  m.origin = "built-in set";
  return m;
}

ModelPtr make_model(const MaterialSpec& material, const std::optional<IgsChoice>& igs,
                    const IntegratorSettings& integrator) {
  switch (material.kind) {
    case ModelKind::hypoplastic:
      return std::make_shared<Hypoplastic>(material.hypoplastic,
                                           igs ? igs->parameters : IntergranularStrainParameters{},
                                           integrator);
    case ModelKind::mohr_coulomb:
      return std::make_shared<MohrCoulomb>(material.mohr_coulomb);
    case ModelKind::linear_elastic:
      return std::make_shared<LinearElastic>(material.elastic);
  }
  throw Error("make_model: unknown model kind");
}

}  // namespace pilempm
