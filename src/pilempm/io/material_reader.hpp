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
#include "pilempm/constitutive/linear_elastic.hpp"
#include "pilempm/constitutive/mohr_coulomb.hpp"
#include "pilempm/io/toml_reader.hpp"

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

/// Reads an igs value: a name (IGS1..IGS4, none) or an inline table {m_R, m_T, R, beta_r, chi},
/// optionally with base = "<IGS set>" and single overrides.
IgsChoice read_igs(TableReader& reader, std::string_view key);

/// Reads an [integrator] table: scheme, tolerance, min_mean_stress_Pa, fixed_substeps,
/// max_substeps, min_substep (all optional; the library's defaults otherwise).
IntegratorSettings read_integrator(TableReader& table);

/// Builds the model. `igs` applies to the hypoplastic model only (nullopt: no intergranular
/// strain); the integrator settings likewise.
ModelPtr make_model(const MaterialSpec& material, const std::optional<IgsChoice>& igs,
                    const IntegratorSettings& integrator);

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
