#pragma once
// Hypoplasticity for sand after von Wolffersdorff (1996), Mech. Cohes.-Frict. Mater. 1, 251-271,
// with the intergranular strain of Niemunis & Herle (1997), Mech. Cohes.-Frict. Mater. 2,
// 279-299, exactly as written in docs/model.md §2-§6, integrated by the explicit embedded
// Runge-Kutta pair of integration/embedded_runge_kutta.hpp with adaptive sub-stepping and local
// error control. This file gives the integrator the rates and the edges of the model's domain.
//
// Treatment of the edges of the model's domain (the model is undefined at tr T = 0):
//  * Tension cut-off. A stage point with a tensile principal stress whose mean stress p is still
//    at least p_min (sand pulled apart in one or two directions, carrying load in the others) has
//    its principal stresses above -p_min set to -p_min (so continuous up to p_min), the principal
//    directions kept, and goes on from there. Before 7 December 2026 such a point went to the
//    isotropic floor below, so that a particle carrying kPa lost all its stress when its smallest
//    principal stress touched zero: a jump in the update that stalled the quasi-static analysis's
//    Newton iterations (docs/quasi-static.md, "Tension cut-off").
//  * Mean stress floor. A trial sub-step that leaves the admissible stress domain otherwise (p
//    below p_min, or a non-finite value) is rejected and the sub-step shrunk.
//    Once the sub-step is below `min_substep` the point has reached the stress-free limit: its
//    stress is set to the isotropic floor -p_min I ("floor hit", counted in UpdateResult). If the
//    rest of the increment still pulls the point apart, the point stays on the floor for the rest
//    of the increment (sand that has lost contact carries no stress); otherwise integration goes
//    on.
//  * Void ratio band. After every accepted sub-step e is clamped to [e_d(p), e_i(p)] (Bauer's
//    law). The model keeps e inside this band in exact arithmetic for monotonic paths; the clamp
//    removes integration drift and the loosening of separated sand. The largest relative distance
//    outside the band before clamping is reported (UpdateResult::void_ratio_excess) so that tests
//    and users can see that it stays at round-off level in ordinary loading.
//  * Intergranular strain: ||delta|| <= R is restored after each accepted sub-step.
#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/integration/embedded_runge_kutta.hpp"

namespace pilempm {

class Hypoplastic final : public ConstitutiveModel {
 public:
  Hypoplastic(const HypoplasticParameters& parameters,
              const IntergranularStrainParameters& intergranular = {},
              const IntegratorSettings& integrator = {});

  /// "hypoplastic", "hypoplastic+IGS", with "+stress-dependent" when that option is on.
  std::string name() const override;
  UpdateResult update(MaterialState& state, const Vec6& strain_increment) const override;
  UpdateResult update_recording(MaterialState& state, const Vec6& strain_increment,
                                SubstepPath& path) const override;
  /// Along the path if it is replayable and stays inside the domain (the end point to the last
  /// bit that of update_recording for the same state and increment), else update().
  UpdateResult update_along(MaterialState& state, const Vec6& strain_increment,
                            const SubstepPath& path) const override;
  Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const override;
  double wave_modulus(const MaterialState& state) const override;
  /// "intergranular_strain" (a tensor, zero without intergranular strain).
  std::span<const HistoryVariable> history_variables() const override;
  /// "igs_rho" = min(1, ||delta|| / R) with intergranular strain, nothing without.
  std::vector<std::string> output_fields() const override;
  double output_field(std::size_t index, const MaterialState& state) const override;

  /// The intergranular strain delta of Niemunis & Herle (1997) in a state's history [-].
  static Eigen::Map<Vec6> intergranular_strain(MaterialState& state) {
    return Eigen::Map<Vec6>(state.history.data());
  }
  static Eigen::Map<const Vec6> intergranular_strain(const MaterialState& state) {
    return Eigen::Map<const Vec6>(state.history.data());
  }

  /// The objective rates of stress, void ratio and intergranular strain for the stretching D.
  struct Rate {
    Vec6 stress;
    double void_ratio;
    Vec6 intergranular_strain;
  };
  Rate rate(const MaterialState& state, const Vec6& stretching) const;

  /// The basic model's linear stiffness L and nonlinear term N at the state (docs/model.md §2-§6),
  /// so that T° = L:D + N ||D|| without intergranular strain.
  struct Terms {
    Mat6 L;
    Vec6 N;
  };
  Terms basic_terms(const MaterialState& state) const;

  const HypoplasticParameters& parameters() const { return parameters_; }
  const IntergranularStrainParameters& intergranular() const { return intergranular_; }
  const IntegratorSettings& integrator() const { return integrator_; }

 private:
  struct Point;      // the integrated variables (stress, void ratio, intergranular strain)
  struct Increment;  // the rate equations for one strain increment, as the integrator sees them
  struct StressFunctions;
  StressFunctions stress_functions(const Vec6& stress, double void_ratio) const;
  // Bauer's factor exp(-x^n) at x = 3p/h_s, as evaluate() found it at its point.
  struct BauerFactor {
    double x = 0.0;          // 3p/h_s
    double x_power_n = 0.0;  // x^n
    double factor = 0.0;     // exp(-x^n)
  };
  BauerFactor evaluate(const Point& y, const Vec6& stretching, Point& rate_out) const;
  bool admissible(const Point& y) const;
  // Tension cut-off: a point whose mean stress is at least p_min but with a tensile principal
  // stress gets its principal stresses above -p_min set to -p_min (directions kept); a point
  // with none, which admissible() rejected by the rounding of its invariants alone, is kept as
  // it is; false where the cut-off cannot bring it back (mean stress below p_min, not finite,
  // e <= 0).
  bool to_domain(Point& y) const;
  double error_norm(const Point& error, const Point& y) const;
  // Keeps e in [e_d(p), e_i(p)] and |delta| <= R. `nearby`: Bauer's factor at a point close to y
  // (saves pow and exp where e is clearly inside the band).
  void restore_bounds(Point& y, UpdateResult& result, const BauerFactor* nearby = nullptr) const;
  bool void_ratio_clearly_inside_band(const Point& y, const BauerFactor& nearby) const;
  void set_to_floor(Point& y) const;
  // update(), update_recording() and update_along(): integrates from the state, adaptively
  // (recording into `record` if given) or along `along`.
  UpdateResult integrate(MaterialState& state, const Vec6& strain_increment, SubstepPath* record,
                         const SubstepPath* along) const;

  HypoplasticParameters parameters_;
  IntergranularStrainParameters intergranular_;
  IntegratorSettings integrator_;
  // Constants of the model that depend on the parameters only.
  double a_;               // a = sqrt3 (3 - sin phi_c) / (2 sqrt2 sin phi_c)
  double f_b_constant_;    // (h_s/n) (e_i0/e_c0)^beta / [3 + a^2 - a sqrt3 (...)^alpha]
  bool stress_dependent_;  // alpha or e_x0 follow the stress level
  double f_b_constant(const HypoplasticParameters::Reference& reference) const;
};

}  // namespace pilempm
