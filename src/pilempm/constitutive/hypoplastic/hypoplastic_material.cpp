#include "pilempm/constitutive/hypoplastic/hypoplastic_material.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"

namespace pilempm {

namespace {

constexpr double kMPa = 1.0e6;
constexpr double kKPa = 1.0e3;

// Library validation names keys in SI; the files name them in their units.
const KeyMap kHypoplasticKeys = {{"h_s_Pa", "h_s_MPa"}};

// Reads `key` into `value`: required when `required`, else an optional override.
void read_into(ParameterSource& t, std::string_view key, double& value, const NumberRange& range,
               bool required, double scale = 1.0) {
  if (required)
    value = t.number(key, range) * scale;
  else if (auto v = t.optional_number(key, range))
    value = *v * scale;
}

}  // namespace

IgsChoice named_igs(std::string_view name) {
  return {std::string(name), intergranular_strain_set(name)};
}

std::vector<std::string> igs_choice_names() {
  return intergranular_strain_set_names();
}

IgsChoice read_igs(ParameterSource& reader, std::string_view key) {
  if (!reader.contains(key)) throw reader.error(key, "missing");
  if (reader.holds_string(key)) return named_igs(reader.choice(key, igs_choice_names()));
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

void write_igs(const IgsChoice& igs, std::string_view key, ParameterSink& out) {
  const std::vector<std::string> names = igs_choice_names();
  if (std::find(names.begin(), names.end(), igs.name) != names.end()) {
    out.text(key, igs.name);
    return;
  }
  out.begin_group(key);
  const std::string_view prefix = "custom (base ";
  if (igs.name.starts_with(prefix) && igs.name.ends_with(")"))
    out.text("base",
             std::string_view(igs.name).substr(prefix.size(), igs.name.size() - prefix.size() - 1));
  const IntergranularStrainParameters& p = igs.parameters;
  out.number("m_R", p.m_R);
  out.number("m_T", p.m_T);
  out.number("R", p.R);
  out.number("beta_r", p.beta_r);
  out.number("chi", p.chi);
  out.end_group();
}

HypoplasticMaterial read_hypoplastic_material(ParameterSource& t) {
  HypoplasticMaterial m;
  if (auto base = t.optional_choice("base", hypoplastic_set_names())) {
    m.base = *base;
    m.parameters = hypoplastic_set(*base);
  }
  const bool required = m.base.empty();
  HypoplasticParameters& p = m.parameters;
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
    // Beyond the study (docs/study.md §5): alpha(p) and Rohe's void ratios, see StressDependence.
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
  return m;
}

namespace {

// The keys of the parameters as read_hypoplastic_material reads them, every parameter written (a
// base set's too, so that a table says what the model uses): for the description (a
// ParameterSink's scaled_number gives the number in the key's unit) and for case files.
void write_parameters(const HypoplasticMaterial& m, ParameterSink& out) {
  if (!m.base.empty()) out.text("base", m.base);
  const HypoplasticParameters& p = m.parameters;
  out.number("phi_c_deg", p.phi_c_deg);
  out.scaled_number("h_s_MPa", p.h_s, kMPa);
  out.number("n", p.n);
  out.number("e_d0", p.e_d0);
  out.number("e_c0", p.e_c0);
  out.number("e_i0", p.e_i0);
  out.number("alpha", p.alpha);
  out.number("beta", p.beta);
  if (p.stress_dependence.enabled()) {
    const StressDependence& d = p.stress_dependence;
    out.begin_group("stress_dependence");
    out.boolean("alpha", d.alpha_varies);
    out.number("alpha_low", d.alpha_low);
    out.number("alpha_high", d.alpha_high);
    out.scaled_number("p_low_kPa", d.p_low, kKPa);
    out.scaled_number("p_high_kPa", d.p_high, kKPa);
    out.boolean("rohe_void_ratios", d.rohe_void_ratios);
    out.end_group();
  }
}

void describe(const HypoplasticMaterial& m, const IntegratorSettings& integrator,
              ParameterSink& out) {
  write_parameters(m, out);
  out.begin_group("igs");
  out.text("name", m.igs ? m.igs->name : "none");
  if (m.igs && m.igs->parameters.enabled()) {
    const IntergranularStrainParameters& g = m.igs->parameters;
    out.number("m_R", g.m_R);
    out.number("m_T", g.m_T);
    out.number("R", g.R);
    out.number("beta_r", g.beta_r);
    out.number("chi", g.chi);
  }
  out.end_group();
  out.begin_group("integrator");
  out.text("scheme", to_string(integrator.scheme));
  out.number("tolerance", integrator.tolerance);
  out.number("min_mean_stress_Pa", integrator.min_mean_stress);
  out.integer("fixed_substeps", integrator.fixed_substeps);
  out.end_group();
}

// A [[material]] table's keys: the parameters and the intergranular strain.
void write(const HypoplasticMaterial& m, ParameterSink& out) {
  write_parameters(m, out);
  if (m.igs) write_igs(*m.igs, "igs", out);
}

}  // namespace

ModelRegistration hypoplastic_registration() {
  return with_parameter_writer<HypoplasticMaterial>(
      make_model_registration<HypoplasticMaterial>(
          "hypoplastic",
          {"base", "phi_c_deg", "h_s_MPa", "n", "e_d0", "e_c0", "e_i0", "alpha", "beta", "igs",
           "stress_dependence"},
          read_hypoplastic_material,
          [](const HypoplasticMaterial& m, const IntegratorSettings& integrator) -> ModelPtr {
            return std::make_shared<Hypoplastic>(
                m.parameters, m.igs ? m.igs->parameters : IntergranularStrainParameters{},
                integrator);
          },
          describe,
          [](const HypoplasticMaterial& m) {  // Jáky
            return 1.0 - std::sin(m.parameters.phi_c_deg * kPi / 180.0);
          }),
      write);
}

}  // namespace pilempm
