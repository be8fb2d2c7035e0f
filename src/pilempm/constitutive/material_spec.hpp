#pragma once
// A material as data: the model kind and its parameter set, a built-in hypoplastic set or one
// read from a case file, with its intergranular strain; and the model built from it. Nothing
// here reads files (io/material_reader.hpp reads [[material]] tables into these).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/linear_elastic.hpp"
#include "pilempm/constitutive/mohr_coulomb.hpp"

namespace pilempm {

enum class ModelKind { hypoplastic, mohr_coulomb, linear_elastic };

/// "hypoplastic", "mohr-coulomb", "linear-elastic".
std::string_view to_string(ModelKind kind);

/// The intergranular strain of a hypoplastic model and where it came from.
struct IgsChoice {
  std::string name;  ///< "IGS1".."IGS4", "none", or "custom" (an inline table)
  IntergranularStrainParameters parameters;
};

/// A named IGS set ("IGS1".."IGS4", "none"); throws InvalidValue listing the names.
IgsChoice named_igs(std::string_view name);
/// "IGS1", ..., "none": what an igs key may name.
std::vector<std::string> igs_choice_names();

/// One material: a built-in hypoplastic set or a [[material]] of a case file.
struct MaterialSpec {
  std::string name;
  ModelKind kind = ModelKind::hypoplastic;
  bool builtin = false;  ///< a named set of the library, not a [[material]] table
  std::string base;      ///< the named set a hypoplastic material started from ("" if none)
  HypoplasticParameters hypoplastic{};
  std::optional<IgsChoice> igs;  ///< the material's own intergranular strain, if it sets one
  ElasticParameters elastic{};
  MohrCoulombParameters mohr_coulomb{};
  std::string note;
  std::string origin;  ///< "built-in set" or "file:line"
};

/// A built-in hypoplastic set as a material (throws InvalidValue for an unknown name).
MaterialSpec builtin_material(std::string_view set_name);

/// Builds the model. `igs` applies to the hypoplastic model only (nullopt: no intergranular
/// strain); the integrator settings likewise.
ModelPtr make_model(const MaterialSpec& material, const std::optional<IgsChoice>& igs,
                    const IntegratorSettings& integrator);

}  // namespace pilempm
