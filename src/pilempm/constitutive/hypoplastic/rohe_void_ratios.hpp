#pragma once
// Rohe's (2010) stress-dependent reference void ratios (docs/study.md §3). An analytical relation,
// kept in the constitutive layer because the stress-dependent option of the hypoplastic model
// uses it; `pilempm analytic rohe` prints it.

namespace pilempm {

/// The reference void ratios e_c0*, e_d0*, e_i0* that Rohe (2010) fitted as functions of the
/// vertical effective stress.
struct RoheReferenceVoidRatios {
  double e_c0 = 0.0;  ///< critical void ratio at zero pressure [-]
  double e_d0 = 0.0;  ///< minimum void ratio at zero pressure [-]
  double e_i0 = 0.0;  ///< maximum void ratio at zero pressure [-]
};

/// Rohe (2010) at vertical effective stress `vertical_stress` [Pa] (>= 0; the fit takes MPa).
/// Throws InvalidValue (key "sigma_v_Pa") for a negative or non-finite stress.
RoheReferenceVoidRatios rohe_reference_void_ratios(double vertical_stress);

}  // namespace pilempm
