#pragma once
// Materials from case files: [[material]] tables (hypoplastic, Mohr-Coulomb, linear elastic), the
// named hypoplastic sets usable by name without a table, the intergranular strain ("igs": a named
// set or an inline table) and the [integrator] table. Keys carry their units (h_s_MPa,
// cohesion_kPa); everything returned is SI.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/material_spec.hpp"
#include "pilempm/io/toml_reader.hpp"

namespace pilempm {

/// Reads an igs value: a name (IGS1..IGS4, none) or an inline table {m_R, m_T, R, beta_r, chi},
/// optionally with base = "<IGS set>" and single overrides.
IgsChoice read_igs(TableReader& reader, std::string_view key);

/// Reads an [integrator] table: scheme, tolerance, min_mean_stress_Pa, fixed_substeps,
/// max_substeps, min_substep (all optional; the library's defaults otherwise).
IntegratorSettings read_integrator(TableReader& table);

/// The materials of one document: its [[material]] tables plus the built-in sets, and its
/// [integrator] settings.
class MaterialCatalog {
 public:
  /// Reads the root's "material" array of tables and "integrator" table (both optional).
  void read(TableReader& root);

  /// A [[material]] of the document, or else a built-in set; nullptr when neither.
  const MaterialSpec* find(std::string_view name) const;
  /// Every name `find` knows, the document's materials first.
  std::vector<std::string> names() const;

  const IntegratorSettings& integrator() const { return integrator_; }
  void set_integrator(const IntegratorSettings& settings) { integrator_ = settings; }

 private:
  std::vector<MaterialSpec> materials_;
  std::vector<MaterialSpec> builtins_ = default_builtins();
  IntegratorSettings integrator_{};

  static std::vector<MaterialSpec> default_builtins();
};

}  // namespace pilempm
