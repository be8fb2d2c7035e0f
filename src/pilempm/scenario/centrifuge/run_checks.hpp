#pragma once
// Whether a centrifuge run passes its own checks (docs/verification.md §8, the limits of its
// table): the K0 stress, the equilibrium with the container, the kinetic energy, and no sand in
// the pile or across the axis. A run that fails one still keeps what it computed; the summary
// and the command say FAILED (docs/reliability.md, "Runs that fail their own checks").
#include <string>
#include <vector>

#include "pilempm/scenario/centrifuge/experiment.hpp"

namespace pilempm::scenario {

/// One check of a run against its limit.
struct CentrifugeCheck {
  std::string name;  ///< "K0 stress", "equilibrium", "kinetic energy", "sand in the pile", "axis"
  std::string measure;  ///< what the value is
  double value = 0.0;   ///< in the unit of `limit_text`
  std::string limit_text;
  bool applies = true;  ///< false: the run has no phase the check needs (e.g. no installation)
  bool passed = true;   ///< true when it does not apply
  /// "equilibrium: max |F_head − (R_base − W)| / F_head over windows of 1 D of travel =
  /// 106.85 %, limit 2 %"
  std::string text() const;
};

/// Limits (docs/verification.md §8): K0 error 1 % of ρ N g H; equilibrium 2 % over windows of
/// 1 D of travel (over one-cell windows when the installation is shorter); kinetic energy 1 % of
/// the pile's work; no particle centre deeper than a cell inside the pile; none across the axis.
inline constexpr double kMaxInitialStressError = 0.01;
inline constexpr double kMaxEquilibriumError = 0.02;
inline constexpr double kMaxKineticToWork = 0.01;

/// The checks of a run, in a fixed order; a value that is NaN where the check applies fails.
std::vector<CentrifugeCheck> centrifuge_checks(const CentrifugeSummary& summary);

/// The checks of `checks` that failed.
std::vector<CentrifugeCheck> failed_checks(const std::vector<CentrifugeCheck>& checks);

}  // namespace pilempm::scenario
