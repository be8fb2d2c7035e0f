#pragma once
// Bauer's (1996) compression law: the limit void ratios of the hypoplastic model against mean
// stress. docs/model.md §2-§6 and §4.
#include <span>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"

namespace pilempm {

/// Bauer (1996): e_p = e_p0 exp[-(3 p / h_s)^n] at mean stress `mean_stress` [Pa] (>= 0), for a
/// reference void ratio `e_p0` at zero pressure, granular hardness `h_s` [Pa] and exponent `n`.
/// Throws InvalidValue (keys "e_p0", "h_s_Pa", "n", "p_Pa") for an input outside its range.
double bauer_void_ratio(double e_p0, double h_s, double n, double mean_stress);

/// One row of a compression table: the limit void ratios at one mean stress.
struct BauerRow {
  double mean_stress = 0.0;  ///< p [Pa]
  LimitVoidRatios limits{};  ///< e_d, e_c, e_i at p
};

/// e_d, e_c and e_i of `parameters` at each of `mean_stresses` [Pa] (each >= 0), in the given
/// order. Only h_s, n, e_d0, e_c0 and e_i0 are used and checked (0 < e_d0 < e_c0 < e_i0); throws
/// InvalidValue naming the key ("h_s_Pa", "n", "e_d0", "e_c0", "e_i0", "p_Pa") otherwise.
std::vector<BauerRow> bauer_table(const HypoplasticParameters& parameters,
                                  std::span<const double> mean_stresses);

}  // namespace pilempm
