// The Mohr-Coulomb model as a [[material]]: its reader, description and registration (see
// model_registry.hpp). Keys carry their units (young_modulus_MPa, cohesion_kPa).
#include <fmt/format.h>

#include <cmath>

#include "pilempm/constitutive/model_registry.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

namespace pilempm {

namespace {

constexpr double kMPa = 1.0e6;
constexpr double kKPa = 1.0e3;

MohrCoulombParameters read(ParameterSource& t) {
  MohrCoulombParameters p;
  p.young_modulus = t.number("young_modulus_MPa", NumberRange::positive()) * kMPa;
  p.poisson_ratio = t.number("poisson_ratio", NumberRange::open(-1.0, 0.5));
  p.cohesion = t.number("cohesion_kPa", NumberRange::non_negative()) * kKPa;
  p.friction_angle_deg = t.number("friction_angle_deg", {0.0, 90.0, false, true});
  p.dilatancy_angle_deg =
      t.number("dilatancy_angle_deg", NumberRange::closed(0.0, p.friction_angle_deg));
  if (auto cutoff = t.optional_number("tension_cutoff_kPa", NumberRange::non_negative())) {
    // Checked here in the file's unit; the library's message would give the apex in Pa.
    const double apex_kPa = p.apex_stress() / kKPa;
    if (std::isfinite(apex_kPa) && *cutoff > apex_kPa)
      throw t.error("tension_cutoff_kPa",
                    fmt::format("out of range: must be in [0, c cot(phi) = {:.6g}] kPa (the "
                                "Mohr-Coulomb apex); leave the key out for no cut-off",
                                apex_kPa));
    p.tension_cutoff = *cutoff * kKPa;
  }
  try {
    p.validate();
  } catch (const InvalidValue& e) {
    throw t.error_from(e, {{"young_modulus_Pa", "young_modulus_MPa"},
                           {"cohesion_Pa", "cohesion_kPa"},
                           {"tension_cutoff_Pa", "tension_cutoff_kPa"}});
  }
  return p;
}

void describe(const MohrCoulombParameters& p, const IntegratorSettings&, ParameterSink& out) {
  out.number("young_modulus_MPa", p.young_modulus / kMPa);
  out.number("poisson_ratio", p.poisson_ratio);
  out.number("cohesion_kPa", p.cohesion / kKPa);
  out.number("friction_angle_deg", p.friction_angle_deg);
  out.number("dilatancy_angle_deg", p.dilatancy_angle_deg);
  out.number("tension_cutoff_kPa", p.tension_cutoff / kKPa);  // no value: no cut-off
}

// The keys `read` reads; no tension_cutoff_kPa when there is no cut-off.
void write(const MohrCoulombParameters& p, ParameterSink& out) {
  out.scaled_number("young_modulus_MPa", p.young_modulus, kMPa);
  out.number("poisson_ratio", p.poisson_ratio);
  out.scaled_number("cohesion_kPa", p.cohesion, kKPa);
  out.number("friction_angle_deg", p.friction_angle_deg);
  out.number("dilatancy_angle_deg", p.dilatancy_angle_deg);
  if (std::isfinite(p.tension_cutoff))
    out.scaled_number("tension_cutoff_kPa", p.tension_cutoff, kKPa);
}

}  // namespace

ModelRegistration mohr_coulomb_registration() {
  return with_parameter_writer<MohrCoulombParameters>(
      make_model_registration<MohrCoulombParameters>(
          "mohr-coulomb",
          {"young_modulus_MPa", "poisson_ratio", "cohesion_kPa", "friction_angle_deg",
           "dilatancy_angle_deg", "tension_cutoff_kPa"},
          read,
          [](const MohrCoulombParameters& p, const IntegratorSettings&) -> ModelPtr {
            return std::make_shared<MohrCoulomb>(p);
          },
          describe,
          [](const MohrCoulombParameters& p) {  // Jáky with the friction angle
            return 1.0 - std::sin(p.friction_angle_deg * kPi / 180.0);
          }),
      write);
}

}  // namespace pilempm
