#include "pilempm/analytic/herle_gudehus.hpp"

#include <fmt/format.h>
#include <cmath>

#include "pilempm/analytic/bolton.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm {

namespace {

void require(bool condition, const char* key, double value, const std::string& allowed) {
  if (!condition) throw InvalidValue(key, format_value(value), allowed);
}

double degrees_to_radians(double degrees) {
  return degrees * kPi / 180.0;
}

}  // namespace

double hypoplastic_factor_a(double phi_c_deg) {
  require(phi_c_deg > 0.0 && phi_c_deg < 90.0, "phi_c_deg", phi_c_deg, "in (0, 90) degrees");
  const double sin_phi_c = std::sin(degrees_to_radians(phi_c_deg));
  // von Wolffersdorff (1996): a = sqrt3 (3 - sin phi_c) / (2 sqrt2 sin phi_c).
  return kSqrt3 * (3.0 - sin_phi_c) / (2.0 * kSqrt2 * sin_phi_c);
}

HerleGudehusPeak herle_gudehus_peak(double phi_c_deg, double phi_p_deg) {
  const double a = hypoplastic_factor_a(phi_c_deg);
  require(
      phi_p_deg > phi_c_deg && phi_p_deg < 90.0, "phi_p_deg", phi_p_deg,
      fmt::format("in (phi_c_deg = {}, 90) degrees: a peak above the critical state", phi_c_deg));
  const double sin_phi_p = std::sin(degrees_to_radians(phi_p_deg));
  HerleGudehusPeak peak;
  const double K = (1.0 + sin_phi_p) / (1.0 - sin_phi_p);  // K_p = sigma_1 / sigma_3 at peak
  peak.K_p = K;
  // Herle & Gudehus (1999): A = a^2/(2 + K_p)^2 [1 - K_p (4 - K_p)/(5 K_p - 2)].
  const double A = a * a / ((2.0 + K) * (2.0 + K)) * (1.0 - K * (4.0 - K) / (5.0 * K - 2.0));
  // Herle & Gudehus (1999): tan nu_p = 2 (K_p - 4 + 5 A K_p^2 - 2 A K_p)/((5 K_p - 2)(1 + 2A)) - 1.
  peak.tan_nu_p =
      2.0 * (K - 4.0 + 5.0 * A * K * K - 2.0 * A * K) / ((5.0 * K - 2.0) * (1.0 + 2.0 * A)) - 1.0;
  const double t = peak.tan_nu_p;
  // Herle & Gudehus (1999): f_d = 6 ((2 + K_p)^2 + a^2 K_p (K_p - 1 - tan nu_p))
  //                              / (a (2 + K_p)(5 K_p - 2) sqrt(4 + 2 (1 + tan nu_p)^2)).
  peak.f_d = 6.0 * ((2.0 + K) * (2.0 + K) + a * a * K * (K - 1.0 - t)) /
             (a * (2.0 + K) * (5.0 * K - 2.0) * std::sqrt(4.0 + 2.0 * (1.0 + t) * (1.0 + t)));
  return peak;
}

double alpha_from_peak(double phi_c_deg, double phi_p_deg, double void_ratio, double e_d,
                       double e_c) {
  require(e_d > 0.0 && std::isfinite(e_d), "e_d", e_d, "> 0");
  require(e_c > e_d && std::isfinite(e_c), "e_c", e_c, fmt::format("> e_d = {}", e_d));
  require(void_ratio > e_d && void_ratio < e_c, "e", void_ratio,
          fmt::format("in (e_d, e_c) = ({}, {})", e_d, e_c));
  const HerleGudehusPeak peak = herle_gudehus_peak(phi_c_deg, phi_p_deg);
  // Herle & Gudehus (1999): f_d = ((e - e_d)/(e_c - e_d))^alpha at the peak.
  return std::log(peak.f_d) / std::log((void_ratio - e_d) / (e_c - e_d));
}

std::string_view to_string(AlphaStatus status) {
  switch (status) {
    case AlphaStatus::defined:
      return "defined";
    case AlphaStatus::no_peak:
      return "no_peak";
    case AlphaStatus::e_below_e_d:
      return "e_below_e_d";
    case AlphaStatus::e_above_e_c:
      return "e_above_e_c";
  }
  return "unknown";
}

AlphaPoint alpha_isotropic(const HypoplasticParameters& parameters, double e0,
                           VoidRatioConvention convention, double mean_stress) {
  parameters.validate();
  require(e0 > 0.0 && std::isfinite(e0), "e0", e0, "> 0");
  require(mean_stress > 0.0 && std::isfinite(mean_stress), "p_Pa", mean_stress, "> 0");

  AlphaPoint point;
  point.mean_stress = mean_stress;
  point.void_ratio = initial_void_ratio(parameters, e0, convention, mean_stress);
  const LimitVoidRatios limits = limit_void_ratios(parameters, mean_stress);  // Bauer (1996)
  point.e_d = limits.e_d;
  point.e_c = limits.e_c;
  point.relative_density = (limits.e_c - point.void_ratio) / (limits.e_c - limits.e_d);
  if (point.void_ratio <= limits.e_d) {
    point.status = AlphaStatus::e_below_e_d;
    return point;
  }
  if (point.void_ratio >= limits.e_c) {
    point.status = AlphaStatus::e_above_e_c;
    return point;
  }
  point.phi_p_deg = bolton(point.relative_density, parameters.phi_c_deg, mean_stress).phi_max_deg;
  if (*point.phi_p_deg <= parameters.phi_c_deg) {
    point.status = AlphaStatus::no_peak;
    return point;
  }
  point.alpha = alpha_from_peak(parameters.phi_c_deg, *point.phi_p_deg, point.void_ratio,
                                limits.e_d, limits.e_c);
  point.status = AlphaStatus::defined;
  return point;
}

std::vector<AlphaPoint> alpha_curve(const HypoplasticParameters& parameters, double e0,
                                    VoidRatioConvention convention,
                                    std::span<const double> mean_stresses) {
  std::vector<AlphaPoint> points;
  points.reserve(mean_stresses.size());
  for (const double mean_stress : mean_stresses)
    points.push_back(alpha_isotropic(parameters, e0, convention, mean_stress));
  return points;
}

}  // namespace pilempm
