#include "pilempm/io/material_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace pilempm {

namespace {

constexpr double kMPa = 1.0e6;
constexpr double kKPa = 1.0e3;

// Library validation names keys in SI; the files name them in their units.
const KeyMap kHypoplasticKeys = {{"h_s_Pa", "h_s_MPa"}};
const KeyMap kMohrCoulombKeys = {{"young_modulus_Pa", "young_modulus_MPa"},
                                 {"cohesion_Pa", "cohesion_kPa"},
                                 {"tension_cutoff_Pa", "tension_cutoff_kPa"}};
const KeyMap kElasticKeys = {{"young_modulus_Pa", "young_modulus_MPa"}};

bool safe_name(const std::string& name) {
  if (name.empty() || name.size() > 100) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ||
           c == '+';
  });
}

// Reads `key` into `value`: required when `required`, else an optional override.
void read_into(TableReader& t, std::string_view key, double& value, const NumberRange& range,
               bool required, double scale = 1.0) {
  if (required)
    value = t.number(key, range) * scale;
  else if (auto v = t.optional_number(key, range))
    value = *v * scale;
}

void read_hypoplastic(TableReader& t, MaterialSpec& m) {
  if (auto base = t.optional_choice("base", hypoplastic_set_names())) {
    m.base = *base;
    m.hypoplastic = hypoplastic_set(*base);
  }
  const bool required = m.base.empty();
  HypoplasticParameters& p = m.hypoplastic;
  read_into(t, "phi_c_deg", p.phi_c_deg, NumberRange::open(0.0, 90.0), required);
  read_into(t, "h_s_MPa", p.h_s, NumberRange::positive(), required, kMPa);
  read_into(t, "n", p.n, NumberRange::open(0.0, 1.0), required);
  read_into(t, "e_d0", p.e_d0, NumberRange::positive(), required);
  read_into(t, "e_c0", p.e_c0, NumberRange::positive(), required);
  read_into(t, "e_i0", p.e_i0, NumberRange::positive(), required);
  read_into(t, "alpha", p.alpha, NumberRange::non_negative(), required);
  read_into(t, "beta", p.beta, NumberRange::non_negative(), required);
  if (t.contains("igs")) m.igs = read_igs(t, "igs");
  if (auto sd = t.table("stress_dependence")) {
    // Beyond the study (BRIEF.md §6): alpha(p) and Rohe's void ratios, see StressDependence.
    sd->declare(
        {"alpha", "alpha_low", "alpha_high", "p_low_kPa", "p_high_kPa", "rohe_void_ratios"});
    StressDependence& d = p.stress_dependence;
    d.alpha_varies = sd->boolean_or("alpha", false);
    d.alpha_low = sd->number_or("alpha_low", d.alpha_low, NumberRange::non_negative());
    d.alpha_high = sd->number_or("alpha_high", d.alpha_high, NumberRange::non_negative());
    d.p_low = sd->number_or("p_low_kPa", d.p_low / kKPa, NumberRange::positive()) * kKPa;
    d.p_high = sd->number_or("p_high_kPa", d.p_high / kKPa, NumberRange::positive()) * kKPa;
    d.rohe_void_ratios = sd->boolean_or("rohe_void_ratios", false);
    sd->check_no_unknown_keys();
    try {
      d.validate();
    } catch (const InvalidValue& e) {
      throw sd->error_from(e, {{"p_low_Pa", "p_low_kPa"}, {"p_high_Pa", "p_high_kPa"}});
    }
  }
  try {
    p.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e, kHypoplasticKeys,
                       m.base.empty() ? "" : fmt::format("value from base set \"{}\"", m.base));
  }
}

void read_mohr_coulomb(TableReader& t, MaterialSpec& m) {
  MohrCoulombParameters& p = m.mohr_coulomb;
  p.young_modulus = t.number("young_modulus_MPa", NumberRange::positive()) * kMPa;
  p.poisson_ratio = t.number("poisson_ratio", NumberRange::open(-1.0, 0.5));
  p.cohesion = t.number("cohesion_kPa", NumberRange::non_negative()) * kKPa;
  p.friction_angle_deg = t.number("friction_angle_deg", {0.0, 90.0, false, true});
  p.dilatancy_angle_deg =
      t.number("dilatancy_angle_deg", NumberRange::closed(0.0, p.friction_angle_deg));
  if (auto cutoff = t.optional_number("tension_cutoff_kPa", NumberRange::non_negative())) {
    // Checked here in the file's unit; the library's message would give the apex in Pa.
    const double apex_kPa = p.apex_stress() / kKPa;
    if (std::isfinite(apex_kPa) && *cutoff > apex_kPa)
      throw t.error("tension_cutoff_kPa",
                    fmt::format("out of range: must be in [0, c cot(phi) = {:.6g}] kPa (the "
                                "Mohr-Coulomb apex); leave the key out for no cut-off",
                                apex_kPa));
    p.tension_cutoff = *cutoff * kKPa;
  }
  try {
    p.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e, kMohrCoulombKeys);
  }
}

void read_linear_elastic(TableReader& t, MaterialSpec& m) {
  m.elastic.young_modulus = t.number("young_modulus_MPa", NumberRange::positive()) * kMPa;
  m.elastic.poisson_ratio = t.number("poisson_ratio", NumberRange::open(-1.0, 0.5));
  try {
    m.elastic.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e, kElasticKeys);
  }
}

std::vector<std::string> model_keys(ModelKind kind) {
  switch (kind) {
    case ModelKind::hypoplastic:
      return {"note", "base", "phi_c_deg", "h_s_MPa", "n",   "e_d0",
              "e_c0", "e_i0", "alpha",     "beta",    "igs", "stress_dependence"};
    case ModelKind::mohr_coulomb:
      return {"note",
              "young_modulus_MPa",
              "poisson_ratio",
              "cohesion_kPa",
              "friction_angle_deg",
              "dilatancy_angle_deg",
              "tension_cutoff_kPa"};
    case ModelKind::linear_elastic:
      return {"note", "young_modulus_MPa", "poisson_ratio"};
  }
  return {};
}

const std::vector<std::string> kModelNames = {"hypoplastic", "mohr-coulomb", "linear-elastic"};

}  // namespace

IgsChoice read_igs(TableReader& reader, std::string_view key) {
  const toml::node* node = reader.node(key);
  if (node == nullptr) throw reader.error(key, "missing");
  if (node->is_string()) {
    const std::string name = reader.choice(key, igs_choice_names());
    return named_igs(name);
  }
  auto table = reader.table(key);  // throws "wrong type" for anything but a string or a table
  table->declare({"base", "m_R", "m_T", "R", "beta_r", "chi"});
  IgsChoice choice{"custom", {}};
  std::vector<std::string> bases = igs_choice_names();
  bases.erase(std::remove(bases.begin(), bases.end(), "none"), bases.end());
  bool required = true;
  if (auto base = table->optional_choice("base", bases)) {
    choice.parameters = intergranular_strain_set(*base);
    choice.name = fmt::format("custom (base {})", *base);
    required = false;
  }
  IntergranularStrainParameters& p = choice.parameters;
  read_into(*table, "m_R", p.m_R, NumberRange::at_least(1.0), required);
  read_into(*table, "m_T", p.m_T, NumberRange::at_least(1.0), required);
  read_into(*table, "R", p.R, NumberRange::positive(), required);
  read_into(*table, "beta_r", p.beta_r, NumberRange::positive(), required);
  read_into(*table, "chi", p.chi, NumberRange::positive(), required);
  table->check_no_unknown_keys();
  try {
    p.validate();
  } catch (const InvalidValue& e) {
    throw table->error_from(e, {}, "value from the base set");
  }
  return choice;
}

IntegratorSettings read_integrator(TableReader& t) {
  IntegratorSettings s;
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

void MaterialCatalog::read(TableReader& root) {
  if (auto integrator = root.table("integrator")) integrator_ = read_integrator(*integrator);
  for (TableReader& t : root.tables("material")) {
    MaterialSpec m;
    m.name = t.string("name");
    if (!safe_name(m.name))
      throw t.error("name",
                    "not allowed: must be 1 to 100 letters, digits and the characters - _ . +");
    if (find(m.name) != nullptr)
      throw t.error("name", find(m.name)->builtin
                                ? "already the name of a built-in set: choose another name "
                                  "(or use base = \"" +
                                      m.name + "\" to start from it)"
                                : "a [[material]] of this name is already defined");
    m.kind = static_cast<ModelKind>(
        std::find(kModelNames.begin(), kModelNames.end(), t.choice("model", kModelNames)) -
        kModelNames.begin());
    t.declare(model_keys(m.kind));
    m.note = t.optional_string("note").value_or("");
    m.origin = fmt::format("{}:{}", t.file(), t.line());
    switch (m.kind) {
      case ModelKind::hypoplastic:
        read_hypoplastic(t, m);
        break;
      case ModelKind::mohr_coulomb:
        read_mohr_coulomb(t, m);
        break;
      case ModelKind::linear_elastic:
        read_linear_elastic(t, m);
        break;
    }
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
