#pragma once
// The summary of a centrifuge run that passes its own checks, with the order of magnitude of the
// quick case's figures (docs/verification.md §8): the start of the tests of the checks'
// verdict, which change one figure at a time.
#include "pilempm/scenario/centrifuge/experiment.hpp"

namespace pilempm_test {

inline pilempm::scenario::CentrifugeSummary summary_of_a_good_centrifuge_run() {
  pilempm::scenario::CentrifugeSummary r;
  r.title = "a good run";
  r.initial_stress_error = 0.003;
  r.initial_stress_ratio = 1.0;
  r.installation_head_force = 340.0;
  r.installation_tip_depth_D = 5.0;
  r.equilibrium_error = 0.015;
  r.equilibrium_error_1D = 0.004;
  r.max_kinetic_to_work = 0.0002;
  r.particles_in_pile = 0;
  r.min_radius_mm = 0.4;
  return r;
}

}  // namespace pilempm_test
