#pragma once
// Materials from case files: [[material]] tables of any registered model (the model's own reader,
// from constitutive/model_registry.hpp, reads its keys through a TomlParameterSource), the named
// hypoplastic sets usable by name without a table, the intergranular strain ("igs": a named set
// or an inline table) and the [integrator] table. Keys carry their units (h_s_MPa,
// cohesion_kPa); everything returned is SI.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_material.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/constitutive/material_spec.hpp"
#include "pilempm/constitutive/model_registry.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"
#include "pilempm/io/toml_reader.hpp"

namespace pilempm {

/// Reads an igs value of a case file (see the hypoplastic reader, read_igs).
IgsChoice read_igs(TableReader& reader, std::string_view key);

/// The ParameterSource of a TOML table: how models read their keys from case files.
class TomlParameterSource final : public ParameterSource {
 public:
  explicit TomlParameterSource(TableReader& reader) : reader_(&reader) {}
  explicit TomlParameterSource(TableReader&& reader)
      : owned_(std::make_unique<TableReader>(std::move(reader))), reader_(owned_.get()) {}

  bool contains(std::string_view key) override { return reader_->contains(key); }
  bool holds_string(std::string_view key) override;
  double number(std::string_view key, const NumberRange& range) override {
    return reader_->number(key, range);
  }
  std::optional<double> optional_number(std::string_view key, const NumberRange& range) override {
    return reader_->optional_number(key, range);
  }
  double number_or(std::string_view key, double fallback, const NumberRange& range) override {
    return reader_->number_or(key, fallback, range);
  }
  bool boolean_or(std::string_view key, bool fallback) override {
    return reader_->boolean_or(key, fallback);
  }
  std::string choice(std::string_view key, const std::vector<std::string>& allowed) override {
    return reader_->choice(key, allowed);
  }
  std::optional<std::string> optional_choice(std::string_view key,
                                             const std::vector<std::string>& allowed) override {
    return reader_->optional_choice(key, allowed);
  }
  std::unique_ptr<ParameterSource> table(std::string_view key) override;
  void declare(const std::vector<std::string>& keys) override { reader_->declare(keys); }
  void check_no_unknown_keys() const override { reader_->check_no_unknown_keys(); }
  InputError error(std::string_view key, const std::string& reason) const override {
    return reader_->error(key, reason);
  }
  InputError error_from(const InvalidValue& invalid, const KeyMap& keys = {},
                        const std::string& origin = "") const override {
    return reader_->error_from(invalid, keys, origin);
  }

 private:
  std::unique_ptr<TableReader> owned_;
  TableReader* reader_;
};

/// Reads an [integrator] table: scheme, tolerance, min_mean_stress_Pa, fixed_substeps,
/// max_substeps, min_substep (all optional; `defaults` otherwise).
IntegratorSettings read_integrator(TableReader& table, const IntegratorSettings& defaults = {});

/// The materials of one document: its [[material]] tables plus the built-in sets, and its
/// [integrator] settings.
class MaterialCatalog {
 public:
  /// Reads the root's "material" array of tables and "integrator" table (both optional; what the
  /// latter does not set is taken from `integrator_defaults`).
  void read(TableReader& root, const IntegratorSettings& integrator_defaults = {});

  /// A [[material]] of the document, or else a built-in set; nullptr when neither.
  const MaterialSpec* find(std::string_view name) const;
  /// Every name `find` knows, the document's materials first.
  std::vector<std::string> names() const;

  /// The document's [[material]] tables, in order (not the built-in sets).
  const std::vector<MaterialSpec>& materials() const { return materials_; }
  const IntegratorSettings& integrator() const { return integrator_; }
  void set_integrator(const IntegratorSettings& settings) { integrator_ = settings; }

 private:
  std::vector<MaterialSpec> materials_;
  std::vector<MaterialSpec> builtins_ = default_builtins();
  IntegratorSettings integrator_{};

  static std::vector<MaterialSpec> default_builtins();
};

}  // namespace pilempm
