#pragma once
// Stiffness of a (cyclic) oedometer curve: the curve split into monotonic branches of vertical
// stress (first loading, unloading, reloading, ...), secant constrained moduli
// M = d sigma_v / d eps_v between two stress levels of one branch, and the vertical strain
// accumulated by the cycles. Inputs are compression positive, SI (Pa and strain as a fraction);
// in an oedometer the volumetric strain is the vertical strain.
#include <cstddef>
#include <span>
#include <vector>

namespace pilempm {

/// Rows [first, last] of a curve along which the vertical stress only rises (loading) or only
/// falls (unloading).
struct LoadingBranch {
  std::size_t first = 0, last = 0;
  bool loading = true;
};

/// The branches of a stress history, in order; rows where the stress does not change stay in the
/// current branch. Throws InvalidValue for fewer than two points or a non-finite stress.
std::vector<LoadingBranch> loading_branches(std::span<const double> vertical_stress);

/// Secant constrained modulus (sigma_to - sigma_from) / (eps(sigma_to) - eps(sigma_from)) [Pa]
/// on one branch, the strain at each stress interpolated linearly between the rows around it.
/// Throws InvalidValue when a stress lies outside the branch or the strain does not change.
double secant_modulus(std::span<const double> vertical_stress, std::span<const double> strain,
                      const LoadingBranch& branch, double sigma_from, double sigma_to);

/// What the study compares between the intergranular strain sets.
struct CyclicOedometerStiffness {
  double initial_stress = 0.0;                ///< sigma_v at the start [Pa]
  double first_increment_stress = 0.0;        ///< sigma_v after the first increment [Pa]
  double first_increment_modulus = 0.0;       ///< secant modulus over the first increment [Pa]
  double initial_secant_modulus = 0.0;        ///< first loading, sigma_v0 -> 2 sigma_v0 [Pa]
  double reload_from = 0.0, reload_to = 0.0;  ///< first reloading: its start and twice that [Pa]
  double reload_secant_modulus = 0.0;         ///< [Pa]; 0 when there is no reloading branch
  double strain_after_first_loading = 0.0;    ///< at the end of the first loading branch [-]
  double final_strain = 0.0;                  ///< at the end of the curve [-]
  /// final - after first loading, when the curve ends at the stress of the first loading's end
  /// (as a cyclic programme 400-100-400-... kPa does) [-]; the strain the cycles added.
  double accumulated_strain = 0.0;
  int unload_reload_cycles = 0;  ///< unloading branches followed by a reloading branch
};

/// The analysis above. Needs a first loading branch that reaches twice its initial stress
/// (throws InvalidValue otherwise).
CyclicOedometerStiffness analyse_cyclic_oedometer(std::span<const double> vertical_stress,
                                                  std::span<const double> strain);

}  // namespace pilempm
