#pragma once
// Materials as the case readers make them, built without a file: for the tests of the layers
// below io/ (docs/mpm-case-files.md, [[material]]).
#include <memory>
#include <string>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/constitutive/material_spec.hpp"
#include "pilempm/constitutive/model_registry.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

namespace pilempm::test_support {

/// A linear-elastic [[material]] table: E [Pa] and ν.
inline MaterialSpec linear_elastic_material(std::string name, double young_modulus,
                                            double poisson_ratio) {
  ElasticParameters parameters;
  parameters.young_modulus = young_modulus;
  parameters.poisson_ratio = poisson_ratio;
  MaterialSpec spec;
  spec.name = std::move(name);
  spec.model = "linear-elastic";
  spec.parameters = std::make_shared<const ParametersOf<ElasticParameters>>(parameters);
  spec.origin = "test";
  return spec;
}

/// Mohr-Coulomb parameters: E [Pa], ν, cohesion c [Pa], friction and dilatancy angles [deg] and
/// the tension cut-off t [Pa] (infinite: none).
inline MohrCoulombParameters mohr_coulomb_parameters(double young_modulus, double poisson_ratio,
                                                     double cohesion, double friction_angle_deg,
                                                     double dilatancy_angle_deg,
                                                     double tension_cutoff) {
  MohrCoulombParameters p;
  p.young_modulus = young_modulus;
  p.poisson_ratio = poisson_ratio;
  p.cohesion = cohesion;
  p.friction_angle_deg = friction_angle_deg;
  p.dilatancy_angle_deg = dilatancy_angle_deg;
  p.tension_cutoff = tension_cutoff;
  return p;
}

}  // namespace pilempm::test_support
