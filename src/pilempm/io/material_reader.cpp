#include "pilempm/io/material_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace pilempm {

bool TomlParameterSource::holds_string(std::string_view key) {
  const toml::node* node = reader_->node(key);
  return node != nullptr && node->is_string();
}

std::unique_ptr<ParameterSource> TomlParameterSource::table(std::string_view key) {
  auto table = reader_->table(key);
  if (!table) return nullptr;
  return std::make_unique<TomlParameterSource>(std::move(*table));
}

IgsChoice read_igs(TableReader& reader, std::string_view key) {
  TomlParameterSource source(reader);
  return read_igs(static_cast<ParameterSource&>(source), key);
}

IntegratorSettings read_integrator(TableReader& t, const IntegratorSettings& defaults) {
  IntegratorSettings s = defaults;
  if (auto scheme = t.optional_choice("scheme", {"heun-euler", "bogacki-shampine"}))
    s.scheme = parse_integrator_scheme(*scheme, "scheme");
  s.tolerance = t.number_or("tolerance", s.tolerance, NumberRange::left_open(0.0, 0.1));
  s.min_mean_stress = t.number_or("min_mean_stress_Pa", s.min_mean_stress, NumberRange::positive());
  s.fixed_substeps = t.integer_or("fixed_substeps", s.fixed_substeps, 0, 10'000'000);
  s.max_substeps = t.integer_or("max_substeps", s.max_substeps, 1, 1'000'000'000);
  s.min_substep = t.number_or("min_substep", s.min_substep, NumberRange::open(0.0, 1.0));
  t.check_no_unknown_keys();
  try {
    s.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e);
  }
  return s;
}

std::vector<MaterialSpec> MaterialCatalog::default_builtins() {
  std::vector<MaterialSpec> result;
  for (const auto& name : hypoplastic_set_names()) result.push_back(builtin_material(name));
  return result;
}

void MaterialCatalog::read(TableReader& root, const IntegratorSettings& integrator_defaults) {
  integrator_ = integrator_defaults;
  if (auto integrator = root.table("integrator"))
    integrator_ = read_integrator(*integrator, integrator_defaults);
  for (TableReader& t : root.tables("material")) {
    MaterialSpec m;
    if (!t.contains("name")) (void)t.string("name");  // the error for a missing name
    m.name = t.name_or("name", "");
    if (find(m.name) != nullptr)
      throw t.error("name", find(m.name)->builtin
                                ? "already the name of a built-in set: choose another name "
                                  "(or use base = \"" +
                                      m.name + "\" to start from it)"
                                : "a [[material]] of this name is already defined");
    const ModelRegistry& registry = model_registry();
    m.model = t.choice("model", registry.names());
    const ModelRegistration& model = registry.at(m.model);
    t.declare({"note"});
    t.declare(model.keys);
    m.note = t.optional_string("note").value_or("");
    m.origin = fmt::format("{}:{}", t.file(), t.line());
    TomlParameterSource source(t);
    m.parameters = model.read(source);
    t.check_no_unknown_keys();
    materials_.push_back(std::move(m));
  }
}

const MaterialSpec* MaterialCatalog::find(std::string_view name) const {
  for (const auto& m : materials_)
    if (m.name == name) return &m;
  for (const auto& m : builtins_)
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<std::string> MaterialCatalog::names() const {
  std::vector<std::string> result;
  for (const auto& m : materials_) result.push_back(m.name);
  for (const auto& m : builtins_) result.push_back(m.name);
  return result;
}

}  // namespace pilempm
