#include "pilempm/calibration/calibration_problem.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "pilempm/core/error.hpp"

namespace pilempm::calibration {

namespace {

constexpr double kMPa = 1.0e6;
constexpr double kKPa = 1.0e3;

const std::array<ParameterId, kParameterCount> kAll = {
    ParameterId::phi_c_deg, ParameterId::h_s_MPa, ParameterId::n,     ParameterId::e_d0,
    ParameterId::e_c0,      ParameterId::e_i0,    ParameterId::alpha, ParameterId::beta,
    ParameterId::m_R,       ParameterId::m_T,     ParameterId::R,     ParameterId::beta_r,
    ParameterId::chi};
const std::array<std::string_view, kParameterCount> kNames = {
    "phi_c_deg", "h_s_MPa", "n",   "e_d0", "e_c0",   "e_i0", "alpha",
    "beta",      "m_R",     "m_T", "R",    "beta_r", "chi"};

// The path coordinate of a sequence of abscissa values: the accumulated |change| from `origin`,
// so that a cyclic test (an oedometer loaded, unloaded and reloaded) is matched point by point
// along its loading history; for a monotonic test it is the abscissa minus the origin.
std::vector<double> path_coordinate(const std::vector<double>& x, double origin) {
  std::vector<double> s(x.size());
  double previous = origin, total = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    total += std::abs(x[i] - previous);
    previous = x[i];
    s[i] = total;
  }
  return s;
}

// Linear interpolation of y(s) at `at` (s non-decreasing); clamped at the ends.
double interpolate(const std::vector<double>& s, const std::vector<double>& y, double at) {
  if (at <= s.front()) return y.front();
  if (at >= s.back()) return y.back();
  const auto upper = std::upper_bound(s.begin(), s.end(), at);
  const std::size_t hi = static_cast<std::size_t>(upper - s.begin());
  const std::size_t lo = hi - 1;
  const double ds = s[hi] - s[lo];
  if (!(ds > 0.0)) return y[hi];
  return y[lo] + (y[hi] - y[lo]) * (at - s[lo]) / ds;
}

}  // namespace

std::string_view parameter_name(ParameterId id) {
  return kNames[static_cast<std::size_t>(id)];
}

const std::array<ParameterId, kParameterCount>& all_parameters() {
  return kAll;
}

std::optional<ParameterId> parameter_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return kAll[i];
  return std::nullopt;
}

bool is_igs_parameter(ParameterId id) {
  return static_cast<int>(id) >= static_cast<int>(ParameterId::m_R);
}

double get(const ParameterSet& s, ParameterId id) {
  const HypoplasticParameters& h = s.hypoplastic;
  switch (id) {
    case ParameterId::phi_c_deg:
      return h.phi_c_deg;
    case ParameterId::h_s_MPa:
      return h.h_s / kMPa;
    case ParameterId::n:
      return h.n;
    case ParameterId::e_d0:
      return h.e_d0;
    case ParameterId::e_c0:
      return h.e_c0;
    case ParameterId::e_i0:
      return h.e_i0;
    case ParameterId::alpha:
      return h.alpha;
    case ParameterId::beta:
      return h.beta;
    case ParameterId::m_R:
      return s.igs.m_R;
    case ParameterId::m_T:
      return s.igs.m_T;
    case ParameterId::R:
      return s.igs.R;
    case ParameterId::beta_r:
      return s.igs.beta_r;
    case ParameterId::chi:
      return s.igs.chi;
  }
  return 0.0;
}

void set(ParameterSet& s, ParameterId id, double value) {
  HypoplasticParameters& h = s.hypoplastic;
  switch (id) {
    case ParameterId::phi_c_deg:
      h.phi_c_deg = value;
      break;
    case ParameterId::h_s_MPa:
      h.h_s = value * kMPa;
      break;
    case ParameterId::n:
      h.n = value;
      break;
    case ParameterId::e_d0:
      h.e_d0 = value;
      break;
    case ParameterId::e_c0:
      h.e_c0 = value;
      break;
    case ParameterId::e_i0:
      h.e_i0 = value;
      break;
    case ParameterId::alpha:
      h.alpha = value;
      break;
    case ParameterId::beta:
      h.beta = value;
      break;
    case ParameterId::m_R:
      s.igs.m_R = value;
      break;
    case ParameterId::m_T:
      s.igs.m_T = value;
      break;
    case ParameterId::R:
      s.igs.R = value;
      break;
    case ParameterId::beta_r:
      s.igs.beta_r = value;
      break;
    case ParameterId::chi:
      s.igs.chi = value;
      break;
  }
}

double FreeParameter::value(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  if (log_scale()) return lower * std::pow(upper / lower, u);
  return lower + u * (upper - lower);
}

double FreeParameter::coordinate(double v) const {
  double u =
      log_scale() ? std::log(v / lower) / std::log(upper / lower) : (v - lower) / (upper - lower);
  if (!std::isfinite(u)) u = 0.5;
  return std::clamp(u, 0.0, 1.0);
}

double MeasuredQuantity::scale() const {
  if (values.empty()) return 1.0;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  const double range = *hi - *lo;
  // A flat curve (e.g. a void ratio that hardly moves) is scaled by a small part of its size.
  const double floor = 1e-3 * std::max(std::abs(*hi), std::abs(*lo)) + 1e-12;
  return std::max(range, floor);
}

std::string abscissa_column_of(const ElementTest& test) {
  if (std::holds_alternative<DrainedTriaxialTest>(test) ||
      std::holds_alternative<UndrainedTriaxialTest>(test))
    return "axial_strain_pct";
  if (std::holds_alternative<OedometerTest>(test)) return "sigma_a_kPa";
  if (std::holds_alternative<IsotropicCompressionTest>(test)) return "p_kPa";
  return "";
}

std::vector<std::string> default_quantities_of(const ElementTest& test) {
  if (std::holds_alternative<DrainedTriaxialTest>(test)) return {"q_kPa", "volumetric_strain_pct"};
  if (std::holds_alternative<UndrainedTriaxialTest>(test)) return {"q_kPa", "p_kPa"};
  return {"void_ratio"};
}

const std::vector<std::string>& curve_quantity_columns() {
  static const std::vector<std::string> columns = {"axial_strain_pct",
                                                   "radial_strain_pct",
                                                   "volumetric_strain_pct",
                                                   "sigma_a_kPa",
                                                   "sigma_r_kPa",
                                                   "sigma_l_kPa",
                                                   "p_kPa",
                                                   "q_kPa",
                                                   "void_ratio",
                                                   "phi_mob_deg",
                                                   "igs_rho"};
  return columns;
}

double curve_value(const CurvePoint& c, std::string_view column) {
  if (column == "axial_strain_pct") return 100.0 * c.axial_strain;
  if (column == "radial_strain_pct") return 100.0 * c.radial_strain;
  if (column == "volumetric_strain_pct") return 100.0 * c.volumetric_strain;
  if (column == "sigma_a_kPa") return c.axial_stress / kKPa;
  if (column == "sigma_r_kPa") return c.radial_stress / kKPa;
  if (column == "sigma_l_kPa") return c.lateral_stress / kKPa;
  if (column == "p_kPa") return c.p / kKPa;
  if (column == "q_kPa") return c.q / kKPa;
  if (column == "void_ratio") return c.void_ratio;
  if (column == "phi_mob_deg") return c.phi_mobilised_deg;
  if (column == "igs_rho") return c.igs_ratio;
  throw Error("calibration: unknown curve column \"" + std::string(column) + "\"");
}

ModelPtr make_hypoplastic(const ParameterSet& s, const IntegratorSettings& integrator) {
  return std::make_shared<Hypoplastic>(s.hypoplastic, s.igs, integrator);
}

ParameterSet parameters_at(const CalibrationProblem& problem, const std::vector<double>& u) {
  ParameterSet s = problem.base;
  for (std::size_t i = 0; i < problem.free.size(); ++i)
    set(s, problem.free[i].id, problem.free[i].value(u[i]));
  return s;
}

std::vector<double> coordinates_of(const CalibrationProblem& problem, const ParameterSet& s) {
  std::vector<double> u;
  for (const FreeParameter& f : problem.free) u.push_back(f.coordinate(get(s, f.id)));
  return u;
}

ElementResult run_lab_test(const LabTest& test, const ModelPtr& model) {
  return run_element_test(*model, test.test, test.initial);
}

std::optional<std::vector<std::vector<double>>> simulate(const LabTest& test,
                                                         const ModelPtr& model) {
  ElementResult result;
  try {
    result = run_lab_test(test, model);
  } catch (const Error&) {
    return std::nullopt;
  }
  const std::vector<CurvePoint>& curve = result.curve;
  std::vector<double> x(curve.size());
  for (std::size_t k = 0; k < curve.size(); ++k) x[k] = curve_value(curve[k], test.abscissa_column);
  const std::vector<double> s_model = path_coordinate(x, x.front());
  const std::vector<double> s_data = path_coordinate(test.abscissa, x.front());
  std::vector<std::vector<double>> out;
  std::vector<double> y(curve.size());
  for (const MeasuredQuantity& q : test.quantities) {
    for (std::size_t k = 0; k < curve.size(); ++k) y[k] = curve_value(curve[k], q.column);
    std::vector<double> at(s_data.size());
    for (std::size_t j = 0; j < s_data.size(); ++j) {
      at[j] = interpolate(s_model, y, s_data[j]);
      if (!std::isfinite(at[j])) return std::nullopt;
    }
    out.push_back(std::move(at));
  }
  return out;
}

std::size_t residual_count(const LabTest& test) {
  std::size_t n = 0;
  for (const MeasuredQuantity& q : test.quantities) n += q.values.size();
  return n;
}

std::vector<double> test_residuals(const LabTest& test,
                                   const std::vector<std::vector<double>>& simulated) {
  std::vector<double> r;
  r.reserve(residual_count(test));
  for (std::size_t i = 0; i < test.quantities.size(); ++i) {
    const MeasuredQuantity& q = test.quantities[i];
    const double factor =
        std::sqrt(test.weight * q.weight / static_cast<double>(q.values.size())) / q.scale();
    for (std::size_t j = 0; j < q.values.size(); ++j)
      r.push_back(factor * (simulated[i][j] - q.values[j]));
  }
  return r;
}

double normalised_rms(const MeasuredQuantity& q, const std::vector<double>& simulated) {
  double sum = 0.0;
  for (std::size_t j = 0; j < q.values.size(); ++j) {
    const double d = (simulated[j] - q.values[j]) / q.scale();
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, q.values.size())));
}

void make_synthetic_data(CalibrationProblem& problem, const ParameterSet& truth,
                         double noise_fraction, unsigned seed) {
  const ModelPtr model = make_hypoplastic(truth, problem.integrator);
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (LabTest& t : problem.tests) {
    // The measured points: the model's curve at the given abscissa, or at 41 points along the
    // programme when the test has none yet.
    const ElementResult result = run_lab_test(t, model);
    const std::vector<CurvePoint>& curve = result.curve;
    if (t.abscissa.empty()) {
      const std::size_t points = std::min<std::size_t>(41, curve.size());
      for (std::size_t j = 0; j < points; ++j) {
        const std::size_t k = (j * (curve.size() - 1)) / (points - 1);
        t.abscissa.push_back(curve_value(curve[k], t.abscissa_column));
      }
    }
    for (MeasuredQuantity& q : t.quantities) q.values.assign(t.abscissa.size(), 0.0);
    const auto exact = simulate(t, model);
    if (!exact) throw Error("synthetic data: the model fails on test \"" + t.name + "\"");
    for (std::size_t i = 0; i < t.quantities.size(); ++i) {
      MeasuredQuantity& q = t.quantities[i];
      q.values = (*exact)[i];
      const double sd = noise_fraction * q.scale();
      for (double& v : q.values) v += sd * normal(random);
    }
  }
}

}  // namespace pilempm::calibration
