#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

namespace {

// x^y with the exponents that the named sets use (1, 2, 0.5) done without pow().
inline double power(double x, double y) {
  if (y == 1.0) return x;
  if (y == 2.0) return x * x;
  if (y == 0.5) return std::sqrt(x);
  if (y == 0.0) return 1.0;
  return std::pow(x, y);
}

}  // namespace

// The integrated variables; the same type holds their rates.
struct Hypoplastic::Point {
  Vec6 stress;
  double void_ratio;
  Vec6 delta;

  // this = y + h * k
  void assign_step(const Point& y, double h, const Point& k) {
    stress = y.stress + h * k.stress;
    void_ratio = y.void_ratio + h * k.void_ratio;
    delta = y.delta + h * k.delta;
  }
  // this += h * k
  void add(double h, const Point& k) {
    stress += h * k.stress;
    void_ratio += h * k.void_ratio;
    delta += h * k.delta;
  }
  // this = s * (a - b)
  void assign_scaled_difference(double s, const Point& a, const Point& b) {
    stress = s * (a.stress - b.stress);
    void_ratio = s * (a.void_ratio - b.void_ratio);
    delta = s * (a.delta - b.delta);
  }
  // this = h * (w1 k1 + w2 k2 + w3 k3 + w4 k4)
  void assign_combination(double h, double w1, const Point& k1, double w2, const Point& k2,
                          double w3, const Point& k3, double w4, const Point& k4) {
    stress = h * (w1 * k1.stress + w2 * k2.stress + w3 * k3.stress + w4 * k4.stress);
    void_ratio =
        h * (w1 * k1.void_ratio + w2 * k2.void_ratio + w3 * k3.void_ratio + w4 * k4.void_ratio);
    delta = h * (w1 * k1.delta + w2 * k2.delta + w3 * k3.delta + w4 * k4.delta);
  }
  bool operator==(const Point& other) const {
    return stress == other.stress && void_ratio == other.void_ratio && delta == other.delta;
  }
};

// The stress- and density-dependent functions of von Wolffersdorff's model at one state.
struct Hypoplastic::StressFunctions {
  Vec6 T_hat;      // T / tr T
  Vec6 T_hat_dev;  // T_hat - I/3
  double c;        // f_b f_e / tr(T_hat^2)
  double F;        // Matsuoka-Nakai factor
  double f_d;      // pyknotropy factor
  double x;        // 3p/h_s
  double xn;       // (3p/h_s)^n
  double bauer;    // exp(-(3p/h_s)^n)
};

Hypoplastic::Hypoplastic(const HypoplasticParameters& parameters,
                         const IntergranularStrainParameters& intergranular,
                         const IntegratorSettings& integrator)
    : parameters_(parameters), intergranular_(intergranular), integrator_(integrator) {
  parameters_.validate();
  intergranular_.validate();
  integrator_.validate();
  a_ = hypoplastic_a(parameters_.phi_c_deg);
  stress_dependent_ = parameters_.stress_dependence.enabled();
  f_b_constant_ = f_b_constant(parameters_.reference_at(0.0));
}

double Hypoplastic::f_b_constant(const HypoplasticParameters::Reference& r) const {
  // (h_s/n) (e_i0/e_c0)^beta / [3 + a^2 - a sqrt3 ((e_i0-e_d0)/(e_c0-e_d0))^alpha]
  return (parameters_.h_s / parameters_.n) * std::pow(r.e_i0 / r.e_c0, parameters_.beta) /
         f_b_denominator(parameters_.phi_c_deg, r);
}

namespace {
constexpr HistoryVariable kHistory[] = {{"intergranular_strain", 0, 6, true}};
}  // namespace

std::span<const HistoryVariable> Hypoplastic::history_variables() const {
  return kHistory;
}

std::vector<std::string> Hypoplastic::output_fields() const {
  if (!intergranular_.enabled()) return {};
  return {"igs_rho"};  // ||delta|| / R, the mobilisation of the intergranular strain
}

double Hypoplastic::output_field(std::size_t, const MaterialState& state) const {
  return std::min(1.0, Vec6(intergranular_strain(state)).norm() / intergranular_.R);
}

std::string Hypoplastic::name() const {
  std::string name = intergranular_.enabled() ? "hypoplastic+IGS" : "hypoplastic";
  if (stress_dependent_) name += "+stress-dependent";
  return name;
}

Hypoplastic::StressFunctions Hypoplastic::stress_functions(const Vec6& stress,
                                                           double void_ratio) const {
  const auto& p = parameters_;
  StressFunctions s;
  const double tr_T = trace(stress);  // negative in compression
  s.T_hat = stress / tr_T;
  s.T_hat_dev = deviator(s.T_hat);
  const double tr_T_hat2 = s.T_hat.squaredNorm();
  const double dev2 = s.T_hat_dev.squaredNorm();
  const double tan_psi = kSqrt3 * std::sqrt(dev2);
  double cos3theta = -1.0;
  if (dev2 > 1.0e-30) {
    // cos 3theta = -sqrt6 tr(T*^3) / tr(T*^2)^(3/2), with tr(T*^3) = 3 det T* for a deviator.
    cos3theta = -kSqrt6 * 3.0 * determinant(s.T_hat_dev) / (dev2 * std::sqrt(dev2));
    cos3theta = std::clamp(cos3theta, -1.0, 1.0);
  }
  const double tan2 = tan_psi * tan_psi;
  const double radicand = tan2 / 8.0 + (2.0 - tan2) / (2.0 + kSqrt2 * tan_psi * cos3theta);
  s.F = std::sqrt(std::max(radicand, 0.0)) - tan_psi / (2.0 * kSqrt2);

  // Bauer's law: the limit void ratios share the factor exp[-(3p/h_s)^n], 3p = -tr T.
  const double x = -tr_T / p.h_s;
  const double xn = std::pow(x, p.n);
  const double bauer = std::exp(-xn);
  s.x = x;
  s.xn = xn;
  s.bauer = bauer;
  HypoplasticParameters::Reference r{p.alpha, p.e_d0, p.e_c0, p.e_i0};
  double fb_constant = f_b_constant_;
  if (stress_dependent_) {  // alpha and e_x0 follow the stress level (docs/study.md §5)
    r = p.reference_at(-tr_T / 3.0);
    fb_constant = f_b_constant(r);
  }
  const double e_i = r.e_i0 * bauer, e_c = r.e_c0 * bauer, e_d = r.e_d0 * bauer;
  const double density = std::max((void_ratio - e_d) / (e_c - e_d), 0.0);
  s.f_d = power(density, r.alpha);
  const double f_e = power(e_c / void_ratio, p.beta);
  // f_b = (h_s/n) (e_i0/e_c0)^beta (1+e_i)/e_i (3p/h_s)^(1-n) / [...]
  const double f_b = fb_constant * (1.0 + e_i) / e_i * (x / xn);
  s.c = f_b * f_e / tr_T_hat2;
  return s;
}

Hypoplastic::Terms Hypoplastic::basic_terms(const MaterialState& state) const {
  const StressFunctions s = stress_functions(state.stress, state.void_ratio);
  Terms terms;
  terms.L = s.c * (s.F * s.F * Mat6::Identity() + a_ * a_ * outer(s.T_hat, s.T_hat));
  terms.N = s.c * s.f_d * a_ * s.F * (s.T_hat + s.T_hat_dev);
  return terms;
}

Hypoplastic::BauerFactor Hypoplastic::evaluate(const Point& y, const Vec6& D,
                                               Point& rate_out) const {
  const StressFunctions s = stress_functions(y.stress, y.void_ratio);
  const BauerFactor bauer{s.x, s.xn, s.bauer};
  const double a2 = a_ * a_;
  // L:X = c (F^2 X + a^2 T_hat (T_hat:X))
  const Vec6 L_D = s.c * (s.F * s.F * D + a2 * s.T_hat.dot(D) * s.T_hat);
  const Vec6 N = s.c * s.f_d * a_ * s.F * (s.T_hat + s.T_hat_dev);
  rate_out.void_ratio = (1.0 + y.void_ratio) * trace(D);  // e_dot = (1 + e) tr D

  if (!intergranular_.enabled()) {
    rate_out.stress = L_D + N * D.norm();
    rate_out.delta.setZero();
    return bauer;
  }
  // Niemunis & Herle (1997), docs/model.md §2-§6.
  const auto& igs = intergranular_;
  const double norm_delta = y.delta.norm();
  const double rho = std::min(norm_delta / igs.R, 1.0);
  const Vec6 delta_hat = norm_delta > 0.0 ? Vec6(y.delta / norm_delta) : Vec6(Vec6::Zero());
  const double rho_chi = power(rho, igs.chi);
  const double m = rho_chi * igs.m_T + (1.0 - rho_chi) * igs.m_R;
  const double delta_D = delta_hat.dot(D);
  const Vec6 L_delta = s.c * (s.F * s.F * delta_hat + a2 * s.T_hat.dot(delta_hat) * s.T_hat);
  if (delta_D > 0.0) {
    rate_out.stress =
        m * L_D + (rho_chi * (1.0 - igs.m_T) * delta_D) * L_delta + (rho_chi * delta_D) * N;
    rate_out.delta = D - (power(rho, igs.beta_r) * delta_D) * delta_hat;
  } else {
    rate_out.stress = m * L_D + (rho_chi * (igs.m_R - igs.m_T) * delta_D) * L_delta;
    rate_out.delta = D;
  }
  return bauer;
}

Hypoplastic::Rate Hypoplastic::rate(const MaterialState& state, const Vec6& stretching) const {
  Point y{state.stress, state.void_ratio, intergranular_strain(state)};
  Point k;
  evaluate(y, stretching, k);
  return {k.stress, k.void_ratio, k.delta};
}

Mat6 Hypoplastic::tangent(const MaterialState& state, const Vec6& strain_direction) const {
  const Terms terms = basic_terms(state);
  const double norm_D = strain_direction.norm();
  const Vec6 D_hat = norm_D > 0.0 ? Vec6(strain_direction / norm_D) : Vec6(Vec6::Zero());
  if (!intergranular_.enabled()) return terms.L + outer(terms.N, D_hat);
  const auto& igs = intergranular_;
  const Vec6 delta = intergranular_strain(state);
  const double norm_delta = delta.norm();
  const double rho = std::min(norm_delta / igs.R, 1.0);
  const Vec6 delta_hat = norm_delta > 0.0 ? Vec6(delta / norm_delta) : Vec6(Vec6::Zero());
  const double rho_chi = power(rho, igs.chi);
  const double m = rho_chi * igs.m_T + (1.0 - rho_chi) * igs.m_R;
  const Vec6 L_delta = terms.L * delta_hat;
  if (delta_hat.dot(D_hat) > 0.0)
    return m * terms.L + rho_chi * (1.0 - igs.m_T) * outer(L_delta, delta_hat) +
           rho_chi * outer(terms.N, delta_hat);
  return m * terms.L + rho_chi * (igs.m_R - igs.m_T) * outer(L_delta, delta_hat);
}

double Hypoplastic::wave_modulus(const MaterialState& state) const {
  if (!(mean_stress(state.stress) > 0.0)) return 0.0;
  const StressFunctions s = stress_functions(state.stress, state.void_ratio);
  // The largest eigenvalue of L is c (F^2 + a^2 |T_hat|^2); the stiffest branch scales it by m_R;
  // |N| bounds the nonlinear term. Their sum bounds every constrained modulus of the model.
  const double m_max = intergranular_.enabled() ? intergranular_.m_R : 1.0;
  const double L_max = s.c * (s.F * s.F + a_ * a_ * s.T_hat.squaredNorm());
  const double N_norm = s.c * s.f_d * a_ * std::abs(s.F) * (s.T_hat + s.T_hat_dev).norm();
  return m_max * L_max + N_norm;
}

bool Hypoplastic::admissible(const Point& y) const {
  if (!y.stress.allFinite() || !std::isfinite(y.void_ratio) || !y.delta.allFinite()) return false;
  if (!(y.void_ratio > 0.0)) return false;
  // No tensile principal stress: -T positive semi-definite <=> its invariants are all >= 0.
  const Vec6 c = -y.stress;
  const double I1 = trace(c);
  if (I1 < 3.0 * integrator_.min_mean_stress) return false;  // p >= p_min
  const double I2 = 0.5 * (I1 * I1 - c.squaredNorm());
  return I2 >= 0.0 && determinant(c) >= 0.0;
}

bool Hypoplastic::to_domain(Point& y) const {
  if (!y.stress.allFinite() || !std::isfinite(y.void_ratio) || !(y.void_ratio > 0.0) ||
      !y.delta.allFinite())
    return false;
  const double p_min = integrator_.min_mean_stress;
  if (-trace(y.stress) < 3.0 * p_min) return false;  // the floor's case
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(to_matrix(y.stress));
  Vec3 values = solver.eigenvalues();
  bool cut = false;
  for (int i = 0; i < 3; ++i)
    if (values[i] > -p_min) {
      values[i] = -p_min;
      cut = true;
    }
  // Nothing to cut: every principal stress is compressive and the point lies in the domain;
  // admissible() rejected it by the rounding of its invariants alone (the third principal stress
  // of the order of GPa).
  if (!cut) return true;
  const Mat3& directions = solver.eigenvectors();
  y.stress = from_matrix(directions * values.asDiagonal() * directions.transpose());
  // Every principal stress is now at most -p_min by construction; admissible()'s invariant test
  // would lose that to rounding where two principal stresses are near zero and the third is tens
  // of MPa (its determinant then below the rounding of the others).
  return y.stress.allFinite();
}

double Hypoplastic::error_norm(const Point& error, const Point& y) const {
  const double stress_scale = std::max(y.stress.norm(), integrator_.min_mean_stress);
  double norm = error.stress.norm() / stress_scale;
  norm = std::max(norm, std::abs(error.void_ratio) / (1.0 + y.void_ratio));
  if (intergranular_.enabled()) norm = std::max(norm, error.delta.norm() / intergranular_.R);
  return norm;
}

// Whether e_d(p) <= e <= e_i(p) holds at y for certain, from Bauer's factor f_a = exp(-g_a),
// g_a = x_a^n, known at a nearby x_a, without pow and exp. g(x) = x^n is concave for n <= 1 with
// g(0) = 0, so with r = x / x_a
//   g(x) <= g_a (1 - n + n r)   (the tangent at x_a),   g(x) >= g_a min(1, r)   (the chord to 0),
// and exp(-z) >= 1 - z, exp(z) <= 1 / (1 - z) (z < 1) bound f(x) = exp(-g(x)) from both sides.
// The relative margin 1e-12 covers the rounding of pow and exp: where this says yes,
// limit_void_ratios() would not move e either, so the result is the same as without it.
bool Hypoplastic::void_ratio_clearly_inside_band(const Point& y, const BauerFactor& a) const {
  const auto& p = parameters_;
  if (stress_dependent_ || !(p.n > 0.0 && p.n <= 1.0) || !(a.x > 0.0 && a.factor > 0.0))
    return false;
  const double x = -trace(y.stress) / p.h_s;
  if (!(x > 0.0)) return false;
  const double r = x / a.x;
  const double f_low = a.factor * (1.0 - p.n * a.x_power_n * (r - 1.0));
  const double rise = a.x_power_n * std::max(0.0, 1.0 - r);
  if (!(rise < 0.5)) return false;
  const double f_high = a.factor / (1.0 - rise);
  constexpr double kMargin = 1e-12;
  return y.void_ratio <= p.e_i0 * f_low * (1.0 - kMargin) &&
         y.void_ratio >= p.e_d0 * f_high * (1.0 + kMargin);
}

void Hypoplastic::restore_bounds(Point& y, UpdateResult& result, const BauerFactor* nearby) const {
  if (!(nearby && void_ratio_clearly_inside_band(y, *nearby))) {
    const LimitVoidRatios band = limit_void_ratios(parameters_, mean_stress(y.stress));
    if (y.void_ratio > band.e_i) {
      result.void_ratio_excess = std::max(result.void_ratio_excess, y.void_ratio / band.e_i - 1.0);
      y.void_ratio = band.e_i;
    } else if (y.void_ratio < band.e_d) {
      result.void_ratio_excess = std::max(result.void_ratio_excess, 1.0 - y.void_ratio / band.e_d);
      y.void_ratio = band.e_d;
    }
  }
  if (intergranular_.enabled()) {
    const double norm_delta = y.delta.norm();
    if (norm_delta > intergranular_.R) y.delta *= intergranular_.R / norm_delta;
  }
}

void Hypoplastic::set_to_floor(Point& y) const {
  y.stress = -integrator_.min_mean_stress * identity6();
}

// The rate equations over one strain increment D, integrated over the pseudo-time t in [0, 1]:
// what integrate_embedded_runge_kutta needs (see its header), all inline in this file.
struct Hypoplastic::Increment {
  using Point = Hypoplastic::Point;
  using Hint = Hypoplastic::BauerFactor;
  const Hypoplastic& model;
  const Vec6& D;

  Hint rate(const Point& y, Point& k) const { return model.evaluate(y, D, k); }
  bool admissible(const Point& y) const { return model.admissible(y); }
  bool to_domain(Point& y) const { return model.to_domain(y); }
  double error_norm(const Point& error, const Point& y) const { return model.error_norm(error, y); }
  void restore_bounds(Point& y, UpdateResult& result, const Hint* nearby) const {
    model.restore_bounds(y, result, nearby);
  }
  void set_to_edge(Point& y) const { model.set_to_floor(y); }
  // On the floor the stress stays; e and delta follow their rates.
  void advance_on_edge(Point& y, double dt, const Point& k) const {
    y.void_ratio += dt * k.void_ratio;
    y.delta += dt * k.delta;
  }
  // The intergranular strain relaxes towards its bound at the rate max(beta_r, 1) ||D|| / R (the
  // linearisation of delta' = D - rho^beta_r (delta_hat : D) delta_hat at ||delta|| = R, along
  // and across delta_hat); the stress's own rates are far slower except near p = 0, where the
  // error control shortens the sub-steps.
  double stiffness() const {
    const auto& igs = model.intergranular_;
    if (!igs.enabled()) return 0.0;
    return std::max(igs.beta_r, 1.0) * D.norm() / igs.R;
  }
};

UpdateResult Hypoplastic::update(MaterialState& state, const Vec6& strain_increment) const {
  return integrate(state, strain_increment, nullptr, nullptr);
}

UpdateResult Hypoplastic::update_recording(MaterialState& state, const Vec6& strain_increment,
                                           SubstepPath& path) const {
  path.clear();
  return integrate(state, strain_increment, &path, nullptr);
}

UpdateResult Hypoplastic::update_along(MaterialState& state, const Vec6& strain_increment,
                                       const SubstepPath& path) const {
  if (path.replayable) {
    const UpdateResult replayed = integrate(state, strain_increment, nullptr, &path);
    if (replayed.ok) return replayed;
  }
  return integrate(state, strain_increment, nullptr, nullptr);
}

UpdateResult Hypoplastic::integrate(MaterialState& state, const Vec6& strain_increment,
                                    SubstepPath* record, const SubstepPath* along) const {
  if (!state.stress.allFinite() || !std::isfinite(state.void_ratio) || !(state.void_ratio > 0.0) ||
      !strain_increment.allFinite()) {
    UpdateResult result;
    result.ok = false;
    result.message = "non-finite stress, void ratio or strain increment, or void ratio <= 0";
    return result;
  }
  Point y{state.stress, state.void_ratio, intergranular_strain(state)};
  const Increment increment{*this, strain_increment};
  const UpdateResult result =
      along ? replay_embedded_runge_kutta(increment, y, integrator_, *along)
            : integrate_embedded_runge_kutta(increment, y, integrator_, record);
  if (!result.ok) return result;
  state.stress = y.stress;
  state.void_ratio = y.void_ratio;
  intergranular_strain(state) = y.delta;
  return result;
}

}  // namespace pilempm
