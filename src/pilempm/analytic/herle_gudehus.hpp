#pragma once
// Herle & Gudehus (1999): the exponent alpha of the pyknotropy factor f_d from a peak state in
// triaxial compression, and the alpha(p) curve of the study for isotropic compression.
// docs/study.md §3.
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"

namespace pilempm {

/// a = sqrt3 (3 - sin phi_c) / (2 sqrt2 sin phi_c) of von Wolffersdorff's model (docs/model.md
/// §2-§6).
double hypoplastic_factor_a(double phi_c_deg);

/// The peak state in triaxial compression that Herle & Gudehus (1999) solve for.
struct HerleGudehusPeak {
  double K_p = 0.0;       ///< principal stress ratio at peak, (1 + sin phi_p)/(1 - sin phi_p)
  double tan_nu_p = 0.0;  ///< dilatancy at peak, -(d eps_v)/(d eps_1) [-]; > 0 dilates
  double f_d = 0.0;       ///< pyknotropy factor f_d the model needs to stand at this peak [-]
};

/// K_p, tan nu_p and f_d of the peak with friction angle `phi_p_deg`, for a model with critical
/// friction angle `phi_c_deg`. Needs 0 < phi_c_deg < phi_p_deg < 90 (throws InvalidValue with
/// key "phi_c_deg" or "phi_p_deg").
HerleGudehusPeak herle_gudehus_peak(double phi_c_deg, double phi_p_deg);

/// Herle & Gudehus (1999): alpha = ln f_d / ln[(e - e_d)/(e_c - e_d)] for the peak friction angle
/// `phi_p_deg` reached at void ratio `void_ratio` = e, where `e_d` and `e_c` are the limit void
/// ratios at the peak's pressure and `phi_c_deg` gives the model's a. Needs
/// phi_c < phi_p < 90 deg and 0 < e_d < e < e_c; throws InvalidValue (keys "phi_c_deg",
/// "phi_p_deg", "e_d", "e_c", "e") otherwise.
double alpha_from_peak(double phi_c_deg, double phi_p_deg, double void_ratio, double e_d,
                       double e_c);

/// Why an alpha(p) point has or lacks a value.
enum class AlphaStatus {
  defined,      ///< alpha computed
  no_peak,      ///< phi_p <= phi_c by Bolton: no peak, so no alpha
  e_below_e_d,  ///< e <= e_d: denser than the densest state, no Bolton I_D in [0, 1]
  e_above_e_c,  ///< e >= e_c: looser than critical, no peak
};
std::string_view to_string(AlphaStatus status);

/// One point of the alpha(p) curve for isotropic compression.
struct AlphaPoint {
  double mean_stress = 0.0;         ///< p [Pa]
  double void_ratio = 0.0;          ///< e used at p [-] (see `alpha_isotropic`)
  double e_d = 0.0;                 ///< e_d at p by Bauer's law [-]
  double e_c = 0.0;                 ///< e_c at p by Bauer's law [-]
  double relative_density = 0.0;    ///< I_D = (e_c - e)/(e_c - e_d) [-]; may leave [0, 1]
  std::optional<double> phi_p_deg;  ///< Bolton's phi_max with this I_D; empty if I_D not in [0, 1]
  std::optional<double> alpha;      ///< empty unless status == defined
  AlphaStatus status = AlphaStatus::defined;
};

/// The study's recipe for alpha at mean stress `mean_stress` [Pa] (> 0) in isotropic compression
/// (docs/study.md §3): e_d and e_c from Bauer's law at p, I_D = (e_c - e)/(e_c - e_d), the peak
/// angle phi_p from Bolton (1986) with that I_D at p (with the set's phi_c), and alpha from
/// `alpha_from_peak`. The void ratio e at p depends on `convention`:
///  - at_initial_stress: e = e0 at every pressure (e0 is the void ratio of the state considered;
///    this is the default of the CLI and reproduces the brief's alpha = 0.13 at 100 kPa for
///    e = 0.68 with the original set: 0.1297);
///  - at_zero_pressure: e = e0 exp[-(3p/h_s)^n], i.e. e0 compressed along Bauer's law, so that
///    I_D stays constant with p (gives 0.126 at 100 kPa for e0 = 0.68).
/// Throws InvalidValue for invalid parameters, e0 <= 0 (key "e0") or p <= 0 (key "p_Pa").
AlphaPoint alpha_isotropic(const HypoplasticParameters& parameters, double e0,
                           VoidRatioConvention convention, double mean_stress);

/// `alpha_isotropic` at each of `mean_stresses` [Pa], in the given order.
std::vector<AlphaPoint> alpha_curve(const HypoplasticParameters& parameters, double e0,
                                    VoidRatioConvention convention,
                                    std::span<const double> mean_stresses);

}  // namespace pilempm
