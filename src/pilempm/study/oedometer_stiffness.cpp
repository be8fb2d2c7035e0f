#include "pilempm/study/oedometer_stiffness.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/core/error.hpp"

namespace pilempm {

namespace {

// The strain at `sigma` on a branch, interpolated between the two rows around it.
double strain_at(std::span<const double> stress, std::span<const double> strain,
                 const LoadingBranch& branch, double sigma) {
  const double lo = std::min(stress[branch.first], stress[branch.last]);
  const double hi = std::max(stress[branch.first], stress[branch.last]);
  if (!(sigma >= lo && sigma <= hi))
    throw InvalidValue(
        "sigma_v_Pa", format_value(sigma),
        fmt::format("within the branch, [{}, {}] Pa", format_value(lo), format_value(hi)));
  for (std::size_t i = branch.first; i < branch.last; ++i) {
    const double a = stress[i], b = stress[i + 1];
    if ((sigma - a) * (sigma - b) > 0.0) continue;  // not between these rows
    if (a == b) return strain[i];
    const double t = (sigma - a) / (b - a);
    return strain[i] + t * (strain[i + 1] - strain[i]);
  }
  return strain[branch.last];
}

}  // namespace

std::vector<LoadingBranch> loading_branches(std::span<const double> stress) {
  if (stress.size() < 2)
    throw InvalidValue("curve", fmt::format("{} points", stress.size()), "at least 2 points");
  for (double s : stress)
    if (!std::isfinite(s)) throw InvalidValue("sigma_v_Pa", format_value(s), "finite");
  std::vector<LoadingBranch> branches;
  LoadingBranch current{0, 0, true};
  bool direction_known = false;
  for (std::size_t i = 1; i < stress.size(); ++i) {
    const double change = stress[i] - stress[i - 1];
    if (change != 0.0) {
      const bool rising = change > 0.0;
      if (!direction_known) {
        current.loading = rising;
        direction_known = true;
      } else if (rising != current.loading) {
        branches.push_back(current);
        current = LoadingBranch{i - 1, i - 1, rising};
      }
    }
    current.last = i;
  }
  branches.push_back(current);
  return branches;
}

double secant_modulus(std::span<const double> stress, std::span<const double> strain,
                      const LoadingBranch& branch, double sigma_from, double sigma_to) {
  if (strain.size() != stress.size())
    throw InvalidValue("strain", fmt::format("{} points", strain.size()),
                       fmt::format("as many as the stresses ({})", stress.size()));
  const double d_strain =
      strain_at(stress, strain, branch, sigma_to) - strain_at(stress, strain, branch, sigma_from);
  if (d_strain == 0.0)
    throw InvalidValue("strain", "no change", "a strain that changes between the two stresses");
  return (sigma_to - sigma_from) / d_strain;
}

CyclicOedometerStiffness analyse_cyclic_oedometer(std::span<const double> stress,
                                                  std::span<const double> strain) {
  if (strain.size() != stress.size())
    throw InvalidValue("strain", fmt::format("{} points", strain.size()),
                       fmt::format("as many as the stresses ({})", stress.size()));
  const std::vector<LoadingBranch> branches = loading_branches(stress);
  const LoadingBranch& first = branches.front();
  if (!first.loading || stress[first.last] < 2.0 * stress[0])
    throw InvalidValue("curve", "first branch", "a first loading to at least twice the start");
  CyclicOedometerStiffness r;
  r.initial_stress = stress[0];
  r.first_increment_stress = stress[1];
  r.first_increment_modulus = (stress[1] - stress[0]) / (strain[1] - strain[0]);
  r.initial_secant_modulus = secant_modulus(stress, strain, first, stress[0], 2.0 * stress[0]);
  for (std::size_t b = 1; b < branches.size(); ++b) {
    if (!branches[b].loading) continue;
    const LoadingBranch& reload = branches[b];
    r.reload_from = stress[reload.first];
    r.reload_to = std::min(2.0 * r.reload_from, stress[reload.last]);
    r.reload_secant_modulus = secant_modulus(stress, strain, reload, r.reload_from, r.reload_to);
    break;
  }
  for (std::size_t b = 1; b + 1 < branches.size(); ++b)
    if (!branches[b].loading && branches[b + 1].loading) ++r.unload_reload_cycles;
  r.strain_after_first_loading = strain[first.last];
  r.final_strain = strain.back();
  const double end_stress = stress[first.last];
  r.accumulated_strain = std::abs(stress.back() - end_stress) <= 1e-6 * end_stress
                             ? r.final_strain - r.strain_after_first_loading
                             : std::nan("");
  return r;
}

}  // namespace pilempm
