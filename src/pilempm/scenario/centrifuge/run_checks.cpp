// Whether a centrifuge run passes its own checks: see run_checks.hpp.
#include "pilempm/scenario/centrifuge/run_checks.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

namespace pilempm::scenario {

std::string CentrifugeCheck::text() const {
  if (!applies) return fmt::format("{}: does not apply ({})", name, measure);
  return fmt::format("{}: {} = {}, limit {}", name, measure,
                     std::isfinite(value) ? fmt::format("{:.4g}", value) : std::string("nan"),
                     limit_text);
}

namespace {

// (The strings are constructed, not assigned: GCC 12 warns falsely (-Wrestrict) about assigning
// a string literal to a std::string that was inlined here.)
CentrifugeCheck check(std::string name, std::string measure, double value, std::string limit,
                      bool applies, bool passed) {
  CentrifugeCheck c;
  c.name = std::move(name);
  c.measure = std::move(measure);
  c.value = value;
  c.limit_text = std::move(limit);
  c.applies = applies;
  c.passed = !applies || passed;
  return c;
}

// A ratio in per cent against its limit; a NaN `value` where it applies fails.
CentrifugeCheck ratio_check(std::string name, const std::string& measure, double value,
                            double limit, bool applies) {
  return check(std::move(name), applies ? measure + " [%]" : measure, 100.0 * value,
               fmt::format("{:g} %", 100.0 * limit), applies, value <= limit);
}

}  // namespace

std::vector<CentrifugeCheck> centrifuge_checks(const CentrifugeSummary& r) {
  std::vector<CentrifugeCheck> checks;
  checks.push_back(ratio_check("K0 stress", "max |σv − ρNgz| / ρNgH after the K0 phase",
                               r.initial_stress_error, kMaxInitialStressError, true));
  // Equilibrium and kinetic energy need an installation (its tip depth is NaN without one); a
  // force that is NaN there fails.
  const bool installed = std::isfinite(r.installation_tip_depth_D);
  if (std::isfinite(r.equilibrium_error_1D) || !installed)
    checks.push_back(ratio_check(
        "equilibrium",
        "max |F_head − (R_base − W)| / F_head over windows of 1 D of travel, installation",
        r.equilibrium_error_1D, kMaxEquilibriumError, installed));
  else
    checks.push_back(ratio_check("equilibrium",
                                 "max |F_head − (R_base − W)| / F_head over windows of one cell "
                                 "of travel (installation shorter than 1 D)",
                                 r.equilibrium_error, kMaxEquilibriumError, true));
  checks.push_back(ratio_check(  // NaN: less than 1 D of travel
      "kinetic energy", "max kinetic energy / pile work after the first D of travel",
      r.max_kinetic_to_work, kMaxKineticToWork, installed && !std::isnan(r.max_kinetic_to_work)));
  checks.push_back(
      check("sand in the pile", "particles deeper than one cell inside the pile at a phase end",
            static_cast<double>(r.particles_in_pile), "0", true, r.particles_in_pile == 0));
  checks.push_back(check("axis", "smallest particle radius at a phase end [mm]", r.min_radius_mm,
                         ">= 0", !std::isnan(r.min_radius_mm), r.min_radius_mm >= 0.0));
  return checks;
}

std::vector<CentrifugeCheck> failed_checks(const std::vector<CentrifugeCheck>& checks) {
  std::vector<CentrifugeCheck> failed;
  for (const CentrifugeCheck& c : checks)
    if (!c.passed) failed.push_back(c);
  return failed;
}

}  // namespace pilempm::scenario
