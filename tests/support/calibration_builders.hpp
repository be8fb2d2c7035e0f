#pragma once
// Calibration problems the calibration tests share: synthetic laboratory tests of a known set.
#include <cmath>
#include <string>
#include <utility>

#include "pilempm/calibration/fit.hpp"

namespace pilempm::calibration::test_support {

inline constexpr double kKPa = 1e3;

inline LabTest lab(const std::string& name, ElementTest test, double e0) {
  LabTest t;
  t.name = name;
  t.test = std::move(test);
  t.initial.e0 = e0;
  t.initial.e0_at = VoidRatioConvention::at_initial_stress;
  t.abscissa_column = abscissa_column_of(t.test);
  for (const std::string& c : default_quantities_of(t.test)) t.quantities.push_back({c, {}, 1.0});
  return t;
}

inline DrainedTriaxialTest triaxial(double sigma3_kPa, int steps) {
  DrainedTriaxialTest t;
  t.sigma3 = sigma3_kPa * kKPa;
  t.axial_strain = 0.2;
  t.steps = steps;
  return t;
}

// The tests of the checks: oedometer, isotropic compression and drained triaxial tests at three
// confining pressures (dense) and one loose, as in examples/calibration/baskarp.toml, with
// coarser programmes to keep the default suite fast.
inline CalibrationProblem problem_of(const std::string& base, double dense_e0, double loose_e0,
                                     int steps) {
  CalibrationProblem p;
  p.base_set = base;
  p.base.hypoplastic = hypoplastic_set(base);
  p.base.igs = intergranular_strain_set("IGS3");
  p.integrator.tolerance = 1e-3;
  IsotropicCompressionTest iso;
  iso.p0 = 10 * kKPa;
  iso.p_end = 5000 * kKPa;
  iso.steps = steps;
  p.tests.push_back(lab("iso", iso, loose_e0 - 0.05));
  OedometerTest oed;
  oed.sigma_v0 = 10 * kKPa;
  oed.K0 = 1.0 - std::sin(p.base.hypoplastic.phi_c_deg * kPi / 180.0);
  oed.sigma_v_targets = {2000 * kKPa};
  oed.steps_per_segment = steps;
  p.tests.push_back(lab("oed", oed, loose_e0 - 0.1));
  for (double s3 : {50.0, 100.0, 200.0})
    p.tests.push_back(lab("tx-dense-" + std::to_string(int(s3)), triaxial(s3, steps), dense_e0));
  p.tests.push_back(lab("tx-loose", triaxial(100.0, steps), loose_e0));
  p.free = {{ParameterId::phi_c_deg, 25, 40, {}}, {ParameterId::h_s_MPa, 500, 20000, {}},
            {ParameterId::n, 0.2, 0.7, {}},       {ParameterId::e_d0, 0.4, 0.7, {}},
            {ParameterId::e_c0, 0.7, 1.1, {}},    {ParameterId::e_i0, 0.9, 1.4, {}},
            {ParameterId::alpha, 0.01, 0.5, {}},  {ParameterId::beta, 0.5, 2.0, {}}};
  p.max_iterations = 30;
  return p;
}

inline ParameterSet truth_of(const std::string& set) {
  ParameterSet s;
  s.hypoplastic = hypoplastic_set(set);
  s.igs = intergranular_strain_set("IGS3");
  return s;
}

}  // namespace pilempm::calibration::test_support
