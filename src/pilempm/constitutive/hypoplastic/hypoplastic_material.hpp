#pragma once
// The hypoplastic model as a [[material]]: its parameters as read (a named base set, single
// overrides, the optional stress dependence and intergranular strain), their reader and the
// model's registration (see model_registry.hpp). Keys carry their units (h_s_MPa, p_low_kPa).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/model_registry.hpp"

namespace pilempm {

/// The intergranular strain of a hypoplastic model and where it came from.
struct IgsChoice {
  std::string name;  ///< "IGS1".."IGS4", "none", or "custom" (an inline table)
  IntergranularStrainParameters parameters;
};

/// A named IGS set ("IGS1".."IGS4", "none"); throws InvalidValue listing the names.
IgsChoice named_igs(std::string_view name);
/// "IGS1", ..., "none": what an igs key may name.
std::vector<std::string> igs_choice_names();

/// A hypoplastic [[material]] (or built-in set).
struct HypoplasticMaterial {
  HypoplasticParameters parameters{};
  std::string base;              ///< the named set it started from ("" if none)
  std::optional<IgsChoice> igs;  ///< its intergranular strain, if it sets one
};

/// Reads an igs value: a name (IGS1..IGS4, none) or an inline table {m_R, m_T, R, beta_r, chi},
/// optionally with base = "<IGS set>" and single overrides.
IgsChoice read_igs(ParameterSource& source, std::string_view key);

/// Writes an igs value as read_igs reads it back: the set's name, or an inline table (with the
/// base set its name records, "custom (base IGS2)").
void write_igs(const IgsChoice& igs, std::string_view key, ParameterSink& sink);

/// Reads the keys of a hypoplastic [[material]] (see hypoplastic_registration's keys).
HypoplasticMaterial read_hypoplastic_material(ParameterSource& source);

/// The registry entry "hypoplastic".
ModelRegistration hypoplastic_registration();

}  // namespace pilempm
