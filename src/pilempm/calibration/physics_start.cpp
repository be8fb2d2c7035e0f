// Stage 1 of a calibration: a start set from the physics of the measured curves, each parameter
// from the tests that govern it (the order of Herle & Gudehus 1999 and of ExCalibre's
// hierarchical procedure):
//   phi_c      the mobilised friction angle at the end of the triaxial tests that reach a
//              critical state (volumetric rate near zero);
//   h_s, n     Bauer's (1996) law fitted to the first loading branch of the compression curves;
//   e_c0       the void ratio at those critical states, brought to p = 0 by Bauer's law; e_d0
//              and e_i0 keep their ratios to e_c0 from the starting set;
//   alpha      Herle & Gudehus (1999) from the peak states of the triaxial tests;
//   beta       a one-parameter scan against the compression curves (beta scales the stiffness);
//   m_R, m_T   a one-parameter scan of m_R (m_T = 0.4 m_R as in IGS1-4) against the tests with
//              an unloading branch.
// A parameter that is fixed, or has a start value from the user, is left alone.
#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "pilempm/analytic/herle_gudehus.hpp"
#include "pilempm/calibration/fit.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm::calibration {

namespace {

constexpr double kKPa = 1.0e3;
constexpr double kMPa = 1.0e6;

const MeasuredQuantity* quantity(const LabTest& t, std::string_view column) {
  for (const MeasuredQuantity& q : t.quantities)
    if (q.column == column) return &q;
  return nullptr;
}

const FreeParameter* free_parameter(const CalibrationProblem& problem, ParameterId id) {
  for (const FreeParameter& f : problem.free)
    if (f.id == id) return f.start ? nullptr : &f;
  return nullptr;
}

double clamp_to(const FreeParameter& f, double value) {
  return std::clamp(value, f.lower, f.upper);
}

double sin_deg(double deg) {
  return std::sin(deg * kPi / 180.0);
}

// The void ratio of a triaxial test at each measured point: the void_ratio column when there is
// one, else from the volumetric strain (logarithmic, as the driver accumulates it).
std::vector<double> triaxial_void_ratios(const LabTest& t, const HypoplasticParameters& h) {
  if (const MeasuredQuantity* e = quantity(t, "void_ratio")) return e->values;
  std::vector<double> e;
  const MeasuredQuantity* ev = quantity(t, "volumetric_strain_pct");
  if (ev == nullptr) return e;
  const auto& triaxial = std::get<DrainedTriaxialTest>(t.test);
  const double e_start = initial_void_ratio(h, t.initial.e0, t.initial.e0_at, triaxial.sigma3);
  for (double v : ev->values) e.push_back((1.0 + e_start) * std::exp(-v / 100.0) - 1.0);
  return e;
}

struct TriaxialState {
  double phi_deg, p, void_ratio, dilatancy_rate;
};

// The end state of a drained triaxial test and the volumetric rate over its last quarter.
std::optional<TriaxialState> end_state(const LabTest& t, const HypoplasticParameters& h) {
  const MeasuredQuantity* q = quantity(t, "q_kPa");
  if (q == nullptr || q->values.size() < 4) return std::nullopt;
  const double sigma3 = std::get<DrainedTriaxialTest>(t.test).sigma3 / kKPa;
  const double q_end = q->values.back();
  TriaxialState s;
  s.phi_deg = std::asin(q_end / (q_end + 2.0 * sigma3)) * 180.0 / kPi;
  s.p = (sigma3 + q_end / 3.0) * kKPa;
  const std::vector<double> e = triaxial_void_ratios(t, h);
  if (e.empty()) return std::nullopt;
  s.void_ratio = e.back();
  const std::size_t n = t.abscissa.size(), a = n - std::max<std::size_t>(2, n / 4);
  const double d_axial = t.abscissa[n - 1] - t.abscissa[a];
  // de/d eps_a per cent, turned into d eps_v / d eps_a.
  s.dilatancy_rate = d_axial > 0.0 ? -(e[n - 1] - e[a]) / (1.0 + e[n - 1]) * 100.0 / d_axial : 1.0;
  return s;
}

// Golden-section search of one parameter's normalised coordinate over [0, 1] against the given
// tests; returns the best value (case units) or nullopt when every trial failed.
std::optional<double> scan(const FreeParameter& f, const ParameterSet& around,
                           const std::vector<std::size_t>& tests, Evaluator& evaluator,
                           const std::function<void(ParameterSet&, double)>& apply) {
  const auto misfit = [&](double u) {
    ParameterSet s = around;
    apply(s, f.value(u));
    const auto r = evaluator.residuals(s, tests);
    if (!r) return std::numeric_limits<double>::infinity();
    double sum = 0.0;
    for (double x : *r) sum += x * x;
    return sum;
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = 0.0, b = 1.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = misfit(c), fd = misfit(d);
  for (int i = 0; i < 10; ++i) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = misfit(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = misfit(d);
    }
  }
  const double best = fc < fd ? c : d;
  if (!std::isfinite(std::min(fc, fd))) return std::nullopt;
  return f.value(best);
}

bool is_compression(const LabTest& t) {
  return std::holds_alternative<OedometerTest>(t.test) ||
         std::holds_alternative<IsotropicCompressionTest>(t.test);
}

bool has_unloading(const LabTest& t) {
  const auto* oedometer = std::get_if<OedometerTest>(&t.test);
  return oedometer != nullptr && oedometer->sigma_v_targets.size() > 1;
}

}  // namespace

ParameterSet physics_start(const CalibrationProblem& problem, Evaluator& evaluator,
                           std::vector<StartNote>& notes) {
  ParameterSet s = problem.base;
  HypoplasticParameters& h = s.hypoplastic;
  const auto note = [&](ParameterId id, std::string how) {
    notes.push_back({id, get(s, id), std::move(how)});
  };

  // phi_c: the critical states of the triaxial tests.
  std::vector<TriaxialState> critical;
  for (const LabTest& t : problem.tests)
    if (std::holds_alternative<DrainedTriaxialTest>(t.test))
      if (auto e = end_state(t, h); e && std::abs(e->dilatancy_rate) < 0.1) critical.push_back(*e);
  if (const FreeParameter* f = free_parameter(problem, ParameterId::phi_c_deg)) {
    if (!critical.empty()) {
      double sum = 0.0;
      for (const auto& c : critical) sum += c.phi_deg;
      set(s, f->id, clamp_to(*f, sum / static_cast<double>(critical.size())));
      note(f->id, fmt::format("mean end friction angle of {} triaxial test(s) at critical state",
                              critical.size()));
    } else {
      note(f->id, "starting set (no triaxial test ends at a critical state)");
    }
  }

  // h_s and n: Bauer's law through the first loading branch of the compression curves, each
  // curve with its own reference void ratio.
  const FreeParameter* f_hs = free_parameter(problem, ParameterId::h_s_MPa);
  const FreeParameter* f_n = free_parameter(problem, ParameterId::n);
  if (f_hs != nullptr || f_n != nullptr) {
    std::vector<std::vector<std::pair<double, double>>> branches;  // (p [Pa], e)
    const double K0 = 1.0 - sin_deg(h.phi_c_deg);
    for (const LabTest& t : problem.tests) {
      if (!is_compression(t)) continue;
      const MeasuredQuantity* e = quantity(t, "void_ratio");
      if (e == nullptr) continue;
      const bool oedometer = std::holds_alternative<OedometerTest>(t.test);
      std::vector<std::pair<double, double>> branch;
      for (std::size_t j = 0; j < t.abscissa.size(); ++j) {
        if (j > 0 && t.abscissa[j] < t.abscissa[j - 1]) break;  // first unloading
        const double p =
            (oedometer ? t.abscissa[j] * (1.0 + 2.0 * K0) / 3.0 : t.abscissa[j]) * kKPa;
        if (p > 0.0 && e->values[j] > 0.0) branch.emplace_back(p, e->values[j]);
      }
      if (branch.size() >= 4) branches.push_back(std::move(branch));
    }
    if (!branches.empty()) {
      const double hs_lo = f_hs ? f_hs->lower : h.h_s / kMPa, hs_hi = f_hs ? f_hs->upper : hs_lo;
      const double n_lo = f_n ? f_n->lower : h.n, n_hi = f_n ? f_n->upper : n_lo;
      double best = std::numeric_limits<double>::infinity(), best_hs = h.h_s / kMPa, best_n = h.n;
      for (int i = 0; i <= 80; ++i) {
        const double hs = hs_lo * std::pow(hs_hi / hs_lo, i / 80.0) * kMPa;
        for (int k = 0; k <= 60; ++k) {
          const double n = n_lo + (n_hi - n_lo) * k / 60.0;
          double cost = 0.0;
          for (const auto& branch : branches) {
            double mean = 0.0;
            for (const auto& [p, e] : branch) mean += std::log(e) + std::pow(3.0 * p / hs, n);
            mean /= static_cast<double>(branch.size());
            for (const auto& [p, e] : branch) {
              const double d = std::log(e) + std::pow(3.0 * p / hs, n) - mean;
              cost += d * d;
            }
          }
          if (cost < best) {
            best = cost;
            best_hs = hs / kMPa;
            best_n = n;
          }
        }
      }
      if (f_hs) {
        set(s, f_hs->id, best_hs);
        note(f_hs->id, fmt::format("Bauer's law through {} compression curve(s)", branches.size()));
      }
      if (f_n) {
        set(s, f_n->id, best_n);
        note(f_n->id, fmt::format("Bauer's law through {} compression curve(s)", branches.size()));
      }
    } else {
      if (f_hs) note(f_hs->id, "starting set (no compression curve with void_ratio)");
      if (f_n) note(f_n->id, "starting set (no compression curve with void_ratio)");
    }
  }

  // e_c0 from the critical void ratios; e_d0 and e_i0 keep their ratios to e_c0.
  if (const FreeParameter* f = free_parameter(problem, ParameterId::e_c0)) {
    critical.clear();
    for (const LabTest& t : problem.tests)
      if (std::holds_alternative<DrainedTriaxialTest>(t.test))
        if (auto e = end_state(t, h); e && std::abs(e->dilatancy_rate) < 0.1)
          critical.push_back(*e);
    if (!critical.empty()) {
      const double ratio_d = h.e_d0 / h.e_c0, ratio_i = h.e_i0 / h.e_c0;
      double sum = 0.0;
      for (const auto& c : critical)
        sum += c.void_ratio / std::exp(-std::pow(3.0 * c.p / h.h_s, h.n));
      set(s, f->id, clamp_to(*f, sum / static_cast<double>(critical.size())));
      note(f->id, fmt::format("critical void ratio of {} triaxial test(s), Bauer's law to p = 0",
                              critical.size()));
      if (const FreeParameter* fd = free_parameter(problem, ParameterId::e_d0)) {
        set(s, fd->id, clamp_to(*fd, ratio_d * h.e_c0));
        note(fd->id, fmt::format("e_c0 times the starting set's e_d0/e_c0 = {:.3f}", ratio_d));
      }
      if (const FreeParameter* fi = free_parameter(problem, ParameterId::e_i0)) {
        set(s, fi->id, clamp_to(*fi, ratio_i * h.e_c0));
        note(fi->id, fmt::format("e_c0 times the starting set's e_i0/e_c0 = {:.3f}", ratio_i));
      }
    } else {
      note(f->id, "starting set (no triaxial test ends at a critical state)");
    }
  }

  // alpha: Herle & Gudehus (1999) at the peaks of the triaxial tests.
  if (const FreeParameter* f = free_parameter(problem, ParameterId::alpha)) {
    std::vector<double> alphas;
    for (const LabTest& t : problem.tests) {
      if (!std::holds_alternative<DrainedTriaxialTest>(t.test)) continue;
      const MeasuredQuantity* q = quantity(t, "q_kPa");
      const std::vector<double> e = triaxial_void_ratios(t, h);
      if (q == nullptr || e.empty()) continue;
      const auto peak = std::max_element(q->values.begin(), q->values.end());
      const std::size_t k = static_cast<std::size_t>(peak - q->values.begin());
      if (k + 2 >= q->values.size()) continue;  // no peak before the end
      const double sigma3 = std::get<DrainedTriaxialTest>(t.test).sigma3 / kKPa;
      const double phi_p = std::asin(*peak / (*peak + 2.0 * sigma3)) * 180.0 / kPi;
      const LimitVoidRatios limits = limit_void_ratios(h, (sigma3 + *peak / 3.0) * kKPa);
      try {
        alphas.push_back(alpha_from_peak(h.phi_c_deg, phi_p, e[k], limits.e_d, limits.e_c));
      } catch (const InvalidValue&) {
        // This peak is outside the formula's range (phi_p <= phi_c or e outside (e_d, e_c)).
      }
    }
    if (!alphas.empty()) {
      std::sort(alphas.begin(), alphas.end());
      set(s, f->id, clamp_to(*f, alphas[alphas.size() / 2]));
      note(f->id,
           fmt::format("Herle & Gudehus (1999), median over {} triaxial peak(s)", alphas.size()));
    } else {
      note(f->id, "starting set (no triaxial peak for Herle & Gudehus)");
    }
  }

  // beta from the stiffness of the compression curves.
  std::vector<std::size_t> compression, reloading;
  for (std::size_t k = 0; k < problem.tests.size(); ++k) {
    if (is_compression(problem.tests[k])) compression.push_back(k);
    if (has_unloading(problem.tests[k])) reloading.push_back(k);
  }
  if (const FreeParameter* f = free_parameter(problem, ParameterId::beta)) {
    const auto best = compression.empty()
                          ? std::nullopt
                          : scan(*f, s, compression, evaluator,
                                 [&](ParameterSet& x, double v) { set(x, f->id, v); });
    if (best) {
      set(s, f->id, *best);
      note(f->id, fmt::format("scan against {} compression curve(s)", compression.size()));
    } else {
      note(f->id, "starting set (no compression curve)");
    }
  }

  // The intergranular strain from the reloading stiffness.
  if (s.igs.enabled()) {
    const FreeParameter* f_mR = free_parameter(problem, ParameterId::m_R);
    const bool m_T_free = free_parameter(problem, ParameterId::m_T) != nullptr;
    if (f_mR != nullptr) {
      const auto best = reloading.empty()
                            ? std::nullopt
                            : scan(*f_mR, s, reloading, evaluator, [&](ParameterSet& x, double v) {
                                set(x, ParameterId::m_R, v);
                                if (m_T_free) set(x, ParameterId::m_T, std::max(1.0, 0.4 * v));
                              });
      if (best) {
        set(s, ParameterId::m_R, *best);
        note(ParameterId::m_R,
             fmt::format("scan against {} test(s) with unloading", reloading.size()));
        if (m_T_free) {
          set(s, ParameterId::m_T, std::max(1.0, 0.4 * *best));
          note(ParameterId::m_T, "0.4 m_R, the ratio of the sets IGS1-4");
        }
      } else {
        note(ParameterId::m_R, "starting set (no test with unloading)");
      }
    }
  }
  // Keep the limit void ratios ordered for the model.
  if (!(h.e_d0 < h.e_c0 && h.e_c0 < h.e_i0)) {
    h.e_d0 = std::min(h.e_d0, 0.95 * h.e_c0);
    h.e_i0 = std::max(h.e_i0, 1.05 * h.e_c0);
  }
  return s;
}

}  // namespace pilempm::calibration
