#pragma once
// A material as data: the registered model's name and its parameters (of the model's own type,
// type-erased), a built-in hypoplastic set or one read from a case file; and the model built
// from it through the registry. Nothing here reads files (io/material_reader.hpp reads
// [[material]] tables into these through the registry's readers).
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_material.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/model_registry.hpp"

namespace pilempm {

/// One material: a built-in hypoplastic set or a [[material]] of a case file. Its parameters are
/// of its model's own type (the registry's reader made them).
struct MaterialSpec {
  std::string name;
  std::string model = "hypoplastic";  ///< the registered model's name
  bool builtin = false;               ///< a named set of the library, not a [[material]] table
  std::shared_ptr<const ModelParameters> parameters;
  std::string note;
  std::string origin;  ///< "built-in set" or "file:line"

  /// The parameters as the model's type P (nullptr when the material is another model).
  template <class P>
  const P* parameters_as() const {
    return pilempm::parameters_as<P>(parameters.get());
  }
  bool is_hypoplastic() const { return parameters_as<HypoplasticMaterial>() != nullptr; }
  /// The hypoplastic material's parameters (an Error for another model).
  const HypoplasticMaterial& hypoplastic_material() const;
  const HypoplasticParameters& hypoplastic() const { return hypoplastic_material().parameters; }
};

/// The material with the given intergranular strain (hypoplastic materials; others unchanged).
MaterialSpec with_igs(const MaterialSpec& material, const std::optional<IgsChoice>& igs);

/// A built-in hypoplastic set as a material (throws InvalidValue for an unknown name).
MaterialSpec builtin_material(std::string_view set_name);

/// Builds the model through the registry. `igs` applies to the hypoplastic model only (nullopt:
/// no intergranular strain); the integrator settings likewise.
ModelPtr make_model(const MaterialSpec& material, const std::optional<IgsChoice>& igs,
                    const IntegratorSettings& integrator);

}  // namespace pilempm
