#include "pilempm/constitutive/hypoplastic.hpp"

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

void IntegratorSettings::validate() const {
  if (!(tolerance > 0.0 && tolerance <= 0.1))
    throw InvalidValue("tolerance", format_value(tolerance), "in (0, 0.1]");
  if (fixed_substeps < 0)
    throw InvalidValue("fixed_substeps", std::to_string(fixed_substeps), ">= 0 (0: adaptive)");
  if (max_substeps < 1) throw InvalidValue("max_substeps", std::to_string(max_substeps), ">= 1");
  if (!(min_substep > 0.0 && min_substep < 1.0))
    throw InvalidValue("min_substep", format_value(min_substep), "in (0, 1)");
  if (!(min_mean_stress > 0.0 && std::isfinite(min_mean_stress)))
    throw InvalidValue("min_mean_stress_Pa", format_value(min_mean_stress), "> 0");
}

IntegratorSettings::Scheme parse_integrator_scheme(std::string_view text, std::string_view key) {
  if (text == "heun-euler") return IntegratorSettings::Scheme::heun_euler;
  if (text == "bogacki-shampine") return IntegratorSettings::Scheme::bogacki_shampine;
  throw InvalidValue(std::string(key), std::string(text), "\"heun-euler\" or \"bogacki-shampine\"");
}

std::string_view to_string(IntegratorSettings::Scheme scheme) {
  return scheme == IntegratorSettings::Scheme::heun_euler ? "heun-euler" : "bogacki-shampine";
}

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
  if (stress_dependent_) {  // alpha and e_x0 follow the stress level (BRIEF.md §6)
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
  // Niemunis & Herle (1997), BRIEF.md §2.
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
  Point y{state.stress, state.void_ratio, state.intergranular_strain};
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
  const double norm_delta = state.intergranular_strain.norm();
  const double rho = std::min(norm_delta / igs.R, 1.0);
  const Vec6 delta_hat =
      norm_delta > 0.0 ? Vec6(state.intergranular_strain / norm_delta) : Vec6(Vec6::Zero());
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

UpdateResult Hypoplastic::update(MaterialState& state, const Vec6& strain_increment) const {
  UpdateResult result;
  const auto& settings = integrator_;
  Point y{state.stress, state.void_ratio, state.intergranular_strain};
  if (!state.stress.allFinite() || !std::isfinite(state.void_ratio) || !(state.void_ratio > 0.0) ||
      !strain_increment.allFinite()) {
    result.ok = false;
    result.message = "non-finite stress, void ratio or strain increment, or void ratio <= 0";
    return result;
  }
  if (!admissible(y)) {  // starts outside the domain: stress-free sand sits on the floor
    set_to_floor(y);
    ++result.mean_stress_floor_hits;
  }
  const Vec6& D = strain_increment;  // integrated over the pseudo-time t in [0, 1]
  const bool adaptive = settings.fixed_substeps == 0;
  const bool heun = settings.scheme == IntegratorSettings::Scheme::heun_euler;
  // (tolerance / error)^(1 / (order of the error estimate + 1)), without pow() (it ran once a
  // step for every particle of an MPM run).
  auto step_factor = [heun](double ratio) { return heun ? std::sqrt(ratio) : std::cbrt(ratio); };

  double t = 0.0;
  double h = adaptive ? 1.0 : 1.0 / settings.fixed_substeps;
  Point k1, k2, k3, k4, trial, low;
  BauerFactor nearby;  // at the last evaluation, close to the point accepted next
  bool k1_valid = false;
  int attempts = 0;
  while (t < 1.0) {
    if (++attempts > settings.max_substeps) {
      result.ok = false;
      result.message = "hypoplastic integrator: too many sub-steps";
      return result;
    }
    h = std::min(h, 1.0 - t);
    if (!k1_valid) evaluate(y, D, k1);
    double error = 0.0;
    bool inside = true;
    if (heun) {
      // Modified Euler: y1 = y + h k1 (1st order), y2 = y + h/2 (k1 + k2) (2nd order).
      trial.assign_step(y, h, k1);
      inside = admissible(trial);
      if (inside) {
        nearby = evaluate(trial, D, k2);
        trial.assign_step(y, 0.5 * h, k1);
        trial.add(0.5 * h, k2);
        inside = admissible(trial);
        if (inside && adaptive) {
          low.stress = 0.5 * h * (k2.stress - k1.stress);
          low.void_ratio = 0.5 * h * (k2.void_ratio - k1.void_ratio);
          low.delta = 0.5 * h * (k2.delta - k1.delta);
          error = error_norm(low, trial);
        }
      }
    } else {
      // Bogacki & Shampine (1989) RK3(2): c = (0, 1/2, 3/4, 1), FSAL.
      trial.assign_step(y, 0.5 * h, k1);
      inside = admissible(trial);
      if (inside) {
        evaluate(trial, D, k2);
        trial.assign_step(y, 0.75 * h, k2);
        inside = admissible(trial);
      }
      if (inside) {
        evaluate(trial, D, k3);
        trial.assign_step(y, 2.0 / 9.0 * h, k1);
        trial.add(1.0 / 3.0 * h, k2);
        trial.add(4.0 / 9.0 * h, k3);
        inside = admissible(trial);
        if (inside) nearby = evaluate(trial, D, k4);
        if (inside && adaptive) {
          // y3 - y2 with the 2nd-order weights (7/24, 1/4, 1/3, 1/8).
          const double w1 = 2.0 / 9.0 - 7.0 / 24.0, w2 = 1.0 / 3.0 - 0.25,
                       w3 = 4.0 / 9.0 - 1.0 / 3.0, w4 = -0.125;
          low.stress = h * (w1 * k1.stress + w2 * k2.stress + w3 * k3.stress + w4 * k4.stress);
          low.void_ratio = h * (w1 * k1.void_ratio + w2 * k2.void_ratio + w3 * k3.void_ratio +
                                w4 * k4.void_ratio);
          low.delta = h * (w1 * k1.delta + w2 * k2.delta + w3 * k3.delta + w4 * k4.delta);
          error = error_norm(low, trial);
        }
      }
    }

    if (!inside) {
      if (h > settings.min_substep) {  // approach the edge of the domain with smaller steps
        h *= 0.25;
        ++result.rejected_substeps;
        k1_valid = true;
        continue;
      }
      // The edge is reached within min_substep: the point becomes stress-free (floor).
      set_to_floor(y);
      ++result.mean_stress_floor_hits;
      t += h;
      restore_bounds(y, result);
      k1_valid = false;
      // Does the rest of the increment keep pulling the point apart? Then it stays on the floor.
      evaluate(y, D, k1);
      trial.assign_step(y, 1.0 - t, k1);
      if (!admissible(trial)) {
        y.void_ratio += (1.0 - t) * k1.void_ratio;
        y.delta += (1.0 - t) * k1.delta;
        restore_bounds(y, result);
        t = 1.0;
        break;
      }
      k1_valid = true;
      h = 1.0 - t;
      continue;
    }

    if (adaptive && error > settings.tolerance) {
      h *= std::max(0.1, 0.9 * step_factor(settings.tolerance / error));
      ++result.rejected_substeps;
      k1_valid = true;
      if (h < settings.min_substep) {
        result.ok = false;
        result.message = "hypoplastic integrator: sub-step below min_substep at the tolerance";
        return result;
      }
      continue;
    }
    // Accept.
    const Point before = trial;
    y = trial;
    restore_bounds(y, result, &nearby);
    t += h;
    ++result.substeps;
    // FSAL: k4 is the rate at the accepted point unless the bounds moved it.
    if (!heun && y.stress == before.stress && y.void_ratio == before.void_ratio &&
        y.delta == before.delta) {
      k1 = k4;
      k1_valid = true;
    } else {
      k1_valid = false;
    }
    if (adaptive) {
      const double growth = error > 0.0 ? 0.9 * step_factor(settings.tolerance / error) : 4.0;
      h *= std::clamp(growth, 0.2, 4.0);
    }
  }

  state.stress = y.stress;
  state.void_ratio = y.void_ratio;
  state.intergranular_strain = y.delta;
  return result;
}

}  // namespace pilempm
