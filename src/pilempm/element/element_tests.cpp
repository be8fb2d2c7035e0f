#include "pilempm/element/element_tests.hpp"

#include <algorithm>
#include <cmath>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/element/mixed_control_driver.hpp"

namespace pilempm {

namespace {

const Hypoplastic* as_hypoplastic(const ConstitutiveModel& model) {
  return dynamic_cast<const Hypoplastic*>(&model);
}

double igs_ratio(const ConstitutiveModel& model, const MaterialState& state) {
  const Hypoplastic* hypo = as_hypoplastic(model);
  if (hypo == nullptr || !hypo->intergranular().enabled()) return 0.0;
  return Vec6(Hypoplastic::intergranular_strain(state)).norm() / hypo->intergranular().R;
}

CurvePoint curve_point(const MixedControlDriver& driver, const UpdateResult& update) {
  const MaterialState& s = driver.state();
  const Vec6& eps = driver.strain();
  CurvePoint c;
  c.axial_strain = -eps[k11];
  c.radial_strain = -eps[k22];
  c.volumetric_strain = -trace(eps);
  c.axial_stress = -s.stress[k11];
  c.radial_stress = -s.stress[k22];
  c.lateral_stress = -s.stress[k33];
  c.p = mean_stress(s.stress);
  c.q = c.axial_stress - c.radial_stress;
  c.void_ratio = s.void_ratio;
  c.phi_mobilised_deg = mobilised_friction_angle_deg(s.stress);
  c.igs_ratio = igs_ratio(driver.model(), s);
  c.substeps = update.substeps;
  return c;
}

// Collects the curve and the integrator statistics while a programme runs.
class Recorder {
 public:
  Recorder(MixedControlDriver& driver, long total, const ProgressCallback& progress)
      : driver_(driver), total_(total), progress_(progress) {
    UpdateResult none;
    curve_.push_back(curve_point(driver_, none));
  }
  void apply(const MixedIncrement& increment) {
    const UpdateResult r = driver_.apply(increment);
    curve_.push_back(curve_point(driver_, r));
    substeps_ += r.substeps;
    floor_hits_ += r.mean_stress_floor_hits;
    excess_ = std::max(excess_, r.void_ratio_excess);
    if (progress_) progress_(driver_.increments(), total_);
  }
  ElementResult finish(double initial_void_ratio, double initial_p) {
    ElementResult result;
    result.summary = summarise(curve_);
    result.summary.initial_void_ratio = initial_void_ratio;
    result.summary.initial_p = initial_p;
    result.summary.increments = driver_.increments();
    result.summary.substeps = substeps_;
    result.summary.mean_stress_floor_hits = floor_hits_;
    result.summary.max_void_ratio_excess = excess_;
    result.curve = std::move(curve_);
    return result;
  }

 private:
  MixedControlDriver& driver_;
  long total_;
  const ProgressCallback& progress_;
  std::vector<CurvePoint> curve_;
  long substeps_ = 0, floor_hits_ = 0;
  double excess_ = 0.0;
};

MixedIncrement strain_controlled(const Vec6& strain_increment) {
  MixedIncrement m;
  m.strain_increment = strain_increment;
  return m;
}

// Normal components with the given flags stress-controlled at the given targets, the rest
// strain-controlled with the given increments; shear components strain-controlled at zero.
MixedIncrement normal_components(std::array<bool, 3> stress_controlled, const Vec3& targets,
                                 const Vec3& strain_increments) {
  MixedIncrement m;
  for (int i = 0; i < 3; ++i) {
    m.stress_controlled[i] = stress_controlled[i];
    m.stress_target[i] = targets[i];
    m.strain_increment[i] = strain_increments[i];
  }
  return m;
}

void require_positive(double value, const char* key) {
  if (!(value > 0.0) || !std::isfinite(value)) throw InvalidValue(key, format_value(value), "> 0");
}
// A stress checked in Pa but named (and shown) in kPa, the unit of the case files.
void require_positive_kPa(double value_Pa, const char* key) {
  if (!(value_Pa > 0.0) || !std::isfinite(value_Pa))
    throw InvalidValue(key, format_value(value_Pa / 1e3), "> 0");
}
void require_steps(int steps, const char* key) {
  if (steps < 1) throw InvalidValue(key, std::to_string(steps), ">= 1");
}

// With igs = first-increment: delta = R de/||de|| along the strain increment de of the test's
// first increment. Under mixed control de depends on the stiffness, which depends on delta, so
// the direction is a fixed point, found by repeating the first increment from copies of the start.
void align_with_first_increment(const ConstitutiveModel& model, const InitialCondition& initial,
                                MaterialState& start, const MixedIncrement& first) {
  const Hypoplastic* hypo = as_hypoplastic(model);
  if (initial.igs != InitialCondition::Igs::first_increment || hypo == nullptr ||
      !hypo->intergranular().enabled())
    return;
  const double R = hypo->intergranular().R;
  Vec6 direction = first.strain_increment;
  for (int i = 0; i < 6; ++i)
    if (first.stress_controlled[static_cast<std::size_t>(i)]) direction[i] = 0.0;
  if (!(direction.norm() > 0.0)) direction = -identity6();
  direction.normalize();
  for (int iteration = 0; iteration < 20; ++iteration) {
    Hypoplastic::intergranular_strain(start) = R * direction;
    MixedControlDriver probe(model, start);
    probe.apply(first);
    const Vec6 next = probe.last_strain_increment().normalized();
    const bool converged = (next - direction).norm() < 1e-9;
    direction = next;
    if (converged) break;
  }
  Hypoplastic::intergranular_strain(start) = R * direction;
}

}  // namespace

std::string test_type_name(const ElementTest& test) {
  struct Visitor {
    std::string operator()(const IsotropicCompressionTest&) const { return "isotropic"; }
    std::string operator()(const OedometerTest&) const { return "oedometer"; }
    std::string operator()(const DrainedTriaxialTest&) const { return "triaxial"; }
    std::string operator()(const UndrainedTriaxialTest&) const { return "undrained-triaxial"; }
    std::string operator()(const StrainPathTest&) const { return "strain-path"; }
  };
  return std::visit(Visitor{}, test);
}

void validate(const ElementTest& test) {
  struct Visitor {
    void operator()(const IsotropicCompressionTest& t) const {
      require_positive_kPa(t.p0, "p0_kPa");
      require_positive_kPa(t.p_end, "p_end_kPa");
      require_steps(t.steps, "steps");
    }
    void operator()(const OedometerTest& t) const {
      require_positive_kPa(t.sigma_v0, "sigma_v0_kPa");
      require_positive(t.K0, "K0");
      if (t.sigma_v_targets.empty())
        throw InvalidValue("sigma_v_kPa", "[]", "at least one target stress");
      for (double s : t.sigma_v_targets) require_positive_kPa(s, "sigma_v_kPa");
      require_steps(t.steps_per_segment, "steps_per_segment");
    }
    void operator()(const DrainedTriaxialTest& t) const {
      require_positive_kPa(t.sigma3, "sigma3_kPa");
      if (!(t.axial_strain > 0.0 && t.axial_strain < 1.0))
        throw InvalidValue("axial_strain", format_value(t.axial_strain), "in (0, 1)");
      require_steps(t.steps, "steps");
    }
    void operator()(const UndrainedTriaxialTest& t) const {
      require_positive_kPa(t.p0, "p0_kPa");
      if (!(t.axial_strain > 0.0 && t.axial_strain < 1.0))
        throw InvalidValue("axial_strain", format_value(t.axial_strain), "in (0, 1)");
      require_steps(t.steps, "steps");
    }
    void operator()(const StrainPathTest& t) const {
      if (!(mean_stress(t.initial_stress) > 0.0))
        throw InvalidValue("initial_stress_kPa", format_value(mean_stress(t.initial_stress) / 1e3),
                           "a compressive state (p > 0)");
      if (t.segments.empty()) throw InvalidValue("segments", "[]", "at least one segment");
      for (const auto& s : t.segments) require_steps(s.steps, "steps");
    }
  };
  std::visit(Visitor{}, test);
}

MaterialState initial_state(const ConstitutiveModel& model, const Vec6& stress,
                            const InitialCondition& initial) {
  MaterialState state;
  state.stress = stress;
  state.void_ratio = initial.e0;
  if (const Hypoplastic* hypo = as_hypoplastic(model)) {
    state.void_ratio =
        initial_void_ratio(hypo->parameters(), initial.e0, initial.e0_at, mean_stress(stress));
    const double R = hypo->intergranular().R;
    if (hypo->intergranular().enabled() && initial.igs == InitialCondition::Igs::compression)
      Hypoplastic::intergranular_strain(state) = -R / kSqrt3 * identity6();
    if (hypo->intergranular().enabled() && initial.igs == InitialCondition::Igs::tensor) {
      if (!(initial.igs_tensor.norm() <= R * (1.0 + 1e-12)))
        throw InvalidValue("igs_initial", format_value(initial.igs_tensor.norm()),
                           "a tensor with norm <= R = " + format_value(R));
      Hypoplastic::intergranular_strain(state) = initial.igs_tensor;
    }
  }
  return state;
}

std::string_view to_string(InitialCondition::Igs igs) {
  switch (igs) {
    case InitialCondition::Igs::compression:
      return "compression";
    case InitialCondition::Igs::zero:
      return "zero";
    case InitialCondition::Igs::first_increment:
      return "first-increment";
    case InitialCondition::Igs::tensor:
      return "tensor";
  }
  return "?";
}

ElementResult run_element_test(const ConstitutiveModel& model, const ElementTest& test,
                               const InitialCondition& initial, const ProgressCallback& progress) {
  validate(test);
  struct Runner {
    const ConstitutiveModel& model;
    const InitialCondition& initial;
    const ProgressCallback& progress;

    ElementResult operator()(const IsotropicCompressionTest& t) const {
      MaterialState start = initial_state(model, -t.p0 * identity6(), initial);
      const double ratio = std::pow(t.p_end / t.p0, 1.0 / t.steps);
      align_with_first_increment(
          model, initial, start,
          normal_components({true, true, true}, Vec3::Constant(-t.p0 * ratio), Vec3::Zero()));
      MixedControlDriver driver(model, start);
      Recorder recorder(driver, t.steps, progress);
      double p = t.p0;
      for (int i = 0; i < t.steps; ++i) {
        p *= ratio;
        recorder.apply(normal_components({true, true, true}, Vec3::Constant(-p), Vec3::Zero()));
      }
      return recorder.finish(start.void_ratio, t.p0);
    }

    ElementResult operator()(const OedometerTest& t) const {
      const double h0 = t.K0 * t.sigma_v0;
      MaterialState start = initial_state(model, -diagonal6(t.sigma_v0, h0, h0), initial);
      const double first =
          t.sigma_v0 + (t.sigma_v_targets.front() - t.sigma_v0) / t.steps_per_segment;
      align_with_first_increment(
          model, initial, start,
          normal_components({true, false, false}, Vec3(-first, 0, 0), Vec3::Zero()));
      MixedControlDriver driver(model, start);
      const long total = static_cast<long>(t.sigma_v_targets.size()) * t.steps_per_segment;
      Recorder recorder(driver, total, progress);
      double sigma_v = t.sigma_v0;
      for (double target : t.sigma_v_targets) {
        const double step = (target - sigma_v) / t.steps_per_segment;
        for (int i = 1; i <= t.steps_per_segment; ++i) {
          const double s = sigma_v + i * step;
          recorder.apply(normal_components({true, false, false}, Vec3(-s, 0, 0), Vec3::Zero()));
        }
        sigma_v = target;
      }
      return recorder.finish(start.void_ratio, mean_stress(start.stress));
    }

    ElementResult operator()(const DrainedTriaxialTest& t) const {
      MaterialState start = initial_state(model, -t.sigma3 * identity6(), initial);
      const double d_axial = -t.axial_strain / t.steps;
      align_with_first_increment(
          model, initial, start,
          normal_components({false, true, true}, Vec3(0, -t.sigma3, -t.sigma3),
                            Vec3(d_axial, 0, 0)));
      MixedControlDriver driver(model, start);
      Recorder recorder(driver, t.steps, progress);
      for (int i = 0; i < t.steps; ++i)
        recorder.apply(normal_components({false, true, true}, Vec3(0, -t.sigma3, -t.sigma3),
                                         Vec3(d_axial, 0, 0)));
      return recorder.finish(start.void_ratio, t.sigma3);
    }

    ElementResult operator()(const UndrainedTriaxialTest& t) const {
      MaterialState start = initial_state(model, -t.p0 * identity6(), initial);
      const double d_axial = -t.axial_strain / t.steps;
      align_with_first_increment(
          model, initial, start,
          strain_controlled(diagonal6(d_axial, -0.5 * d_axial, -0.5 * d_axial)));
      MixedControlDriver driver(model, start);
      Recorder recorder(driver, t.steps, progress);
      for (int i = 0; i < t.steps; ++i)
        recorder.apply(strain_controlled(diagonal6(d_axial, -0.5 * d_axial, -0.5 * d_axial)));
      return recorder.finish(start.void_ratio, t.p0);
    }

    ElementResult operator()(const StrainPathTest& t) const {
      MaterialState start = initial_state(model, t.initial_stress, initial);
      align_with_first_increment(
          model, initial, start,
          strain_controlled(t.segments.front().strain / t.segments.front().steps));
      MixedControlDriver driver(model, start);
      long total = 0;
      for (const auto& s : t.segments) total += s.steps;
      Recorder recorder(driver, total, progress);
      for (const auto& segment : t.segments)
        for (int i = 0; i < segment.steps; ++i)
          recorder.apply(strain_controlled(segment.strain / segment.steps));
      return recorder.finish(start.void_ratio, mean_stress(start.stress));
    }
  };
  return std::visit(Runner{model, initial, progress}, test);
}

double mobilised_friction_angle_deg(const Vec6& stress) {
  const Vec3 principal = principal_values(-stress);  // compression positive, ascending
  const double s1 = principal[2], s3 = principal[0];
  if (!(s1 + s3 > 0.0)) return 0.0;
  return std::asin(std::clamp((s1 - s3) / (s1 + s3), -1.0, 1.0)) * 180.0 / kPi;
}

double dilatancy_angle_deg(double dilatancy_ratio) {
  // Schanz & Vermeer (1996): sin psi = -(d eps_v/d eps_1) / (2 - d eps_v/d eps_1).
  const double sin_psi = -dilatancy_ratio / (2.0 - dilatancy_ratio);
  return std::asin(std::clamp(sin_psi, -1.0, 1.0)) * 180.0 / kPi;
}

ElementSummary summarise(const std::vector<CurvePoint>& curve) {
  ElementSummary s;
  if (curve.empty()) return s;
  // The peak is the first point that reaches the largest q (to round-off), so that a plateau
  // (perfect plasticity) is found where it starts.
  double largest = curve.front().q;
  for (const CurvePoint& c : curve) largest = std::max(largest, c.q);
  const double reached = largest - 1e-9 * std::abs(largest);
  std::size_t peak = 0;
  while (curve[peak].q < reached) ++peak;
  s.peak_q = curve[peak].q;
  s.axial_strain_at_peak = curve[peak].axial_strain;
  s.phi_at_peak_deg = curve[peak].phi_mobilised_deg;
  s.peak_at_end = peak + 1 == curve.size();
  // The volumetric rate at the peak from the increment that follows it (the one that leaves the
  // peak), or from the one that reached it when the peak is the last point.
  const std::size_t lo = s.peak_at_end ? (peak > 0 ? peak - 1 : 0) : peak;
  const std::size_t hi = s.peak_at_end ? peak : peak + 1;
  const double d_axial = curve[hi].axial_strain - curve[lo].axial_strain;
  if (std::abs(d_axial) > 0.0) {
    s.dilatancy_ratio_at_peak =
        (curve[hi].volumetric_strain - curve[lo].volumetric_strain) / d_axial;
    s.psi_at_peak_deg = dilatancy_angle_deg(s.dilatancy_ratio_at_peak);
  }
  s.final = curve.back();
  return s;
}

}  // namespace pilempm
