#pragma once
// Parameters of the hypoplastic sand model (von Wolffersdorff 1996) and of the intergranular
// strain extension (Niemunis & Herle 1997), the named sets of the Deltares study (docs/model.md
// §2-§6), their validation, and the two conventions for the initial void ratio.
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

/// Beyond the study (docs/study.md §5): the study concludes that alpha should fall gradually as the
/// stress level rises. With `alpha_varies`, alpha follows the mean stress p:
///   alpha(p) = alpha_low                                     for p <= p_low,
///   alpha(p) = alpha_high + (alpha_low - alpha_high) (1 - s(xi)), xi =
///   ln(p/p_low)/ln(p_high/p_low), alpha(p) = alpha_high                                    for p
///   >= p_high,
/// with the smoothstep s(xi) = 3 xi^2 - 2 xi^3, so alpha and its slope are continuous and the
/// stiffness never jumps. The defaults are calibrated at element level
/// (docs/stress-dependent-alpha.md): like the original set (alpha = 0.12) up to 0.2 MPa and like
/// the modified set at 10 MPa (peak friction angles within 1 deg); they follow the fall of the
/// Herle & Gudehus (1999) alpha with pressure. With `rohe_void_ratios`, e_d0, e_c0, e_i0 are
/// replaced by Rohe's (2010) fit evaluated at sigma = p (the fit is in terms of the vertical
/// stress; p is its isotropic stand-in). Both are off by default: the model is then exactly von
/// Wolffersdorff's.
struct StressDependence {
  bool alpha_varies = false;
  double alpha_low = 0.12;   ///< alpha at and below p_low [-]
  double alpha_high = 0.01;  ///< alpha at and above p_high [-]
  double p_low = 0.2e6;      ///< [Pa]
  double p_high = 10.0e6;    ///< [Pa], > p_low
  bool rohe_void_ratios = false;

  bool enabled() const { return alpha_varies || rohe_void_ratios; }
  /// alpha(p) of the law above (the caller checks alpha_varies).
  double alpha(double mean_stress) const;
  void validate() const;
};

/// The eight parameters of von Wolffersdorff's model. SI units (h_s in Pa, phi_c in degrees).
struct HypoplasticParameters {
  double phi_c_deg = 0.0;                ///< critical-state friction angle [deg], in (0, 90)
  double h_s = 0.0;                      ///< granular hardness [Pa], > 0
  double n = 0.0;                        ///< exponent of Bauer's compression law [-], in (0, 1)
  double e_d0 = 0.0;                     ///< minimum void ratio at zero pressure [-]
  double e_c0 = 0.0;                     ///< critical void ratio at zero pressure [-]
  double e_i0 = 0.0;                     ///< maximum void ratio at zero pressure [-]
  double alpha = 0.0;                    ///< exponent of the pyknotropy factor f_d [-], >= 0
  double beta = 0.0;                     ///< exponent of the pyknotropy factor f_e [-], >= 0
  StressDependence stress_dependence{};  ///< off by default

  /// The values of alpha, e_d0, e_c0, e_i0 in force at mean stress p [Pa]: the constants, or
  /// those of the stress-dependent option.
  struct Reference {
    double alpha, e_d0, e_c0, e_i0;
  };
  Reference reference_at(double mean_stress) const;

  /// Throws InvalidValue naming the first impossible value and its allowed range.
  void validate() const;
};

/// The five parameters of the intergranular strain. R = 0 switches it off (basic model).
struct IntergranularStrainParameters {
  double m_R = 1.0;     ///< stiffness factor after a 180 deg reversal [-], >= m_T
  double m_T = 1.0;     ///< stiffness factor after a 90 deg change [-], >= 1
  double R = 0.0;       ///< size of the elastic range [-], > 0 when enabled
  double beta_r = 1.0;  ///< evolution exponent [-], > 0
  double chi = 1.0;     ///< interpolation exponent [-], > 0

  bool enabled() const { return R > 0.0; }
  void validate() const;
};

/// a = sqrt3 (3 - sin phi_c) / (2 sqrt2 sin phi_c) of von Wolffersdorff (1996).
double hypoplastic_a(double phi_c_deg);
/// 3 + a^2 - a sqrt3 ((e_i0 - e_d0)/(e_c0 - e_d0))^alpha, the denominator of f_b (must be > 0).
double f_b_denominator(double phi_c_deg, const HypoplasticParameters::Reference& reference);

/// The named sets. `hypoplastic_set` and `intergranular_strain_set` throw InvalidValue with the
/// list of known names when the name is unknown.
HypoplasticParameters hypoplastic_set(std::string_view name);
IntergranularStrainParameters intergranular_strain_set(std::string_view name);
std::vector<std::string> hypoplastic_set_names();
std::vector<std::string> intergranular_strain_set_names();

/// Which state the given initial void ratio e0 refers to (docs/model.md §2-§6).
enum class VoidRatioConvention {
  at_initial_stress,  ///< e0 is the void ratio at the initial stress, used as it is
  at_zero_pressure,   ///< e0 is a reference at p = 0, scaled to p0 by Bauer's law
};

/// Parses "initial-stress" or "zero-pressure" (throws InvalidValue otherwise).
VoidRatioConvention parse_void_ratio_convention(std::string_view text, std::string_view key);
std::string_view to_string(VoidRatioConvention convention);

/// The void ratio to start from: e0 itself, or e0 exp[-(3 p0 / h_s)^n] (Bauer 1996).
double initial_void_ratio(const HypoplasticParameters& parameters, double e0,
                          VoidRatioConvention convention, double mean_stress);

/// Limit void ratios of Bauer's law at mean stress p [Pa]: e_x0 exp[-(3p/h_s)^n] (with the
/// stress-dependent e_x0 when that option is on).
struct LimitVoidRatios {
  double e_d, e_c, e_i;
};
LimitVoidRatios limit_void_ratios(const HypoplasticParameters& parameters, double mean_stress);

}  // namespace pilempm
