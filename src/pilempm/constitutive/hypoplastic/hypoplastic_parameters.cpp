#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <cmath>

#include "pilempm/constitutive/hypoplastic/rohe_void_ratios.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm {

namespace {

struct NamedHypoplasticSet {
  const char* name;
  HypoplasticParameters parameters;
};

constexpr double kMPa = 1.0e6;

// docs/model.md §2-§6, Baskarp sand. The modified sets keep n = 0.42 (the report's table omits n).
const NamedHypoplasticSet kHypoplasticSets[] = {
    {"original", {31.0, 4000.0 * kMPa, 0.42, 0.548, 0.929, 1.08, 0.12, 0.96, {}}},
    {"loose-fit", {31.0, 2000.0 * kMPa, 0.42, 0.548, 0.929, 1.08, 0.12, 0.96, {}}},
    {"modified-medium-dense", {30.0, 4000.0 * kMPa, 0.42, 0.51, 0.88, 1.01, 0.03, 0.96, {}}},
    {"modified-loose", {30.0, 2000.0 * kMPa, 0.42, 0.51, 0.88, 1.01, 0.03, 0.96, {}}},
    {"modified-medium-dense-alpha0.06",
     {30.0, 4000.0 * kMPa, 0.42, 0.51, 0.88, 1.01, 0.06, 0.96, {}}},
    {"modified-loose-alpha0.06", {30.0, 2000.0 * kMPa, 0.42, 0.51, 0.88, 1.01, 0.06, 0.96, {}}},
};

struct NamedIgsSet {
  const char* name;
  IntergranularStrainParameters parameters;
};

// docs/model.md §2-§6: IGS 1 after Niemunis & Herle (1997), IGS 2 after Pham et al. (2010).
const NamedIgsSet kIgsSets[] = {
    {"IGS1", {5.0, 2.0, 1.0e-4, 0.5, 6.0}}, {"IGS2", {5.0, 2.0, 1.0e-4, 1.0, 2.0}},
    {"IGS3", {5.0, 2.0, 1.0e-4, 1.0, 1.0}}, {"IGS4", {5.0, 2.0, 5.0e-5, 1.0, 1.0}},
    {"none", {1.0, 1.0, 0.0, 1.0, 1.0}},
};

void require(bool condition, const char* key, double value, const std::string& allowed) {
  if (!condition) throw InvalidValue(key, format_value(value), allowed);
}

}  // namespace

double hypoplastic_a(double phi_c_deg) {
  const double sin_phi = std::sin(phi_c_deg * kPi / 180.0);
  return kSqrt3 * (3.0 - sin_phi) / (2.0 * kSqrt2 * sin_phi);  // von Wolffersdorff (1996)
}

double f_b_denominator(double phi_c_deg, const HypoplasticParameters::Reference& r) {
  const double a = hypoplastic_a(phi_c_deg);
  return 3.0 + a * a - a * kSqrt3 * std::pow((r.e_i0 - r.e_d0) / (r.e_c0 - r.e_d0), r.alpha);
}

double StressDependence::alpha(double mean_stress) const {
  if (!(mean_stress > p_low)) return alpha_low;
  if (mean_stress >= p_high) return alpha_high;
  const double xi = std::log(mean_stress / p_low) / std::log(p_high / p_low);
  const double smooth = xi * xi * (3.0 - 2.0 * xi);
  return alpha_high + (alpha_low - alpha_high) * (1.0 - smooth);
}

void StressDependence::validate() const {
  if (!alpha_varies) return;
  require(alpha_low >= 0.0 && std::isfinite(alpha_low), "alpha_low", alpha_low, ">= 0");
  require(alpha_high >= 0.0 && std::isfinite(alpha_high), "alpha_high", alpha_high, ">= 0");
  require(p_low > 0.0 && std::isfinite(p_low), "p_low_Pa", p_low, "> 0");
  require(p_high > p_low && std::isfinite(p_high), "p_high_Pa", p_high,
          fmt::format("> p_low = {} Pa", p_low));
}

HypoplasticParameters::Reference HypoplasticParameters::reference_at(double mean_stress) const {
  Reference r{alpha, e_d0, e_c0, e_i0};
  if (stress_dependence.alpha_varies) r.alpha = stress_dependence.alpha(mean_stress);
  if (stress_dependence.rohe_void_ratios) {
    const RoheReferenceVoidRatios rohe = rohe_reference_void_ratios(std::max(mean_stress, 0.0));
    r.e_d0 = rohe.e_d0;
    r.e_c0 = rohe.e_c0;
    r.e_i0 = rohe.e_i0;
  }
  return r;
}

namespace {
void check_f_b_denominator(const HypoplasticParameters& p, const char* key, double value,
                           const HypoplasticParameters::Reference& r) {
  require(f_b_denominator(p.phi_c_deg, r) > 0.0, key, value,
          "small enough that 3 + a^2 - a sqrt(3) ((e_i0-e_d0)/(e_c0-e_d0))^alpha > 0");
}
}  // namespace

void HypoplasticParameters::validate() const {
  require(phi_c_deg > 0.0 && phi_c_deg < 90.0, "phi_c_deg", phi_c_deg, "in (0, 90) degrees");
  require(h_s > 0.0 && std::isfinite(h_s), "h_s_Pa", h_s, "> 0");
  require(n > 0.0 && n < 1.0, "n", n, "in (0, 1)");
  require(e_d0 > 0.0 && std::isfinite(e_d0), "e_d0", e_d0, "> 0");
  require(e_c0 > e_d0 && std::isfinite(e_c0), "e_c0", e_c0,
          fmt::format("> e_d0 = {} (e_d0 < e_c0 < e_i0)", e_d0));
  require(e_i0 > e_c0 && std::isfinite(e_i0), "e_i0", e_i0,
          fmt::format("> e_c0 = {} (e_d0 < e_c0 < e_i0)", e_c0));
  require(alpha >= 0.0 && std::isfinite(alpha), "alpha", alpha, ">= 0");
  require(beta >= 0.0 && std::isfinite(beta), "beta", beta, ">= 0");
  // f_b's denominator must stay positive for every alpha and e_x0 the model can use.
  check_f_b_denominator(*this, "alpha", alpha, Reference{alpha, e_d0, e_c0, e_i0});
  stress_dependence.validate();
  if (stress_dependence.enabled()) {
    for (double p : {0.0, 1e4, 1e5, 1e6, 1e7, 1e8}) {
      const Reference r = reference_at(p);
      check_f_b_denominator(*this, stress_dependence.alpha_varies ? "alpha_low" : "alpha", r.alpha,
                            r);
    }
  }
}

void IntergranularStrainParameters::validate() const {
  require(R >= 0.0 && std::isfinite(R), "R", R, ">= 0 (0 switches the intergranular strain off)");
  if (!enabled()) return;
  require(m_T >= 1.0 && std::isfinite(m_T), "m_T", m_T, ">= 1");
  require(m_R >= m_T && std::isfinite(m_R), "m_R", m_R, fmt::format(">= m_T = {}", m_T));
  require(beta_r > 0.0 && std::isfinite(beta_r), "beta_r", beta_r, "> 0");
  require(chi > 0.0 && std::isfinite(chi), "chi", chi, "> 0");
}

HypoplasticParameters hypoplastic_set(std::string_view name) {
  for (const auto& set : kHypoplasticSets)
    if (name == set.name) return set.parameters;
  throw InvalidValue("set", std::string(name),
                     fmt::format("one of {}", fmt::join(hypoplastic_set_names(), ", ")));
}

IntergranularStrainParameters intergranular_strain_set(std::string_view name) {
  for (const auto& set : kIgsSets)
    if (name == set.name) return set.parameters;
  throw InvalidValue("igs", std::string(name),
                     fmt::format("one of {}", fmt::join(intergranular_strain_set_names(), ", ")));
}

std::vector<std::string> hypoplastic_set_names() {
  std::vector<std::string> names;
  for (const auto& set : kHypoplasticSets) names.emplace_back(set.name);
  return names;
}

std::vector<std::string> intergranular_strain_set_names() {
  std::vector<std::string> names;
  for (const auto& set : kIgsSets) names.emplace_back(set.name);
  return names;
}

VoidRatioConvention parse_void_ratio_convention(std::string_view text, std::string_view key) {
  if (text == "initial-stress") return VoidRatioConvention::at_initial_stress;
  if (text == "zero-pressure") return VoidRatioConvention::at_zero_pressure;
  throw InvalidValue(std::string(key), std::string(text),
                     "\"initial-stress\" or \"zero-pressure\"");
}

std::string_view to_string(VoidRatioConvention convention) {
  return convention == VoidRatioConvention::at_initial_stress ? "initial-stress" : "zero-pressure";
}

double initial_void_ratio(const HypoplasticParameters& parameters, double e0,
                          VoidRatioConvention convention, double mean_stress) {
  if (convention == VoidRatioConvention::at_initial_stress) return e0;
  // Bauer (1996): e = e0 exp[-(3 p0 / h_s)^n].
  return e0 * std::exp(-std::pow(3.0 * mean_stress / parameters.h_s, parameters.n));
}

LimitVoidRatios limit_void_ratios(const HypoplasticParameters& parameters, double mean_stress) {
  const double p = std::max(mean_stress, 0.0);
  const double factor = std::exp(-std::pow(3.0 * p / parameters.h_s, parameters.n));
  const HypoplasticParameters::Reference r = parameters.reference_at(p);
  return {r.e_d0 * factor, r.e_c0 * factor, r.e_i0 * factor};
}

}  // namespace pilempm
