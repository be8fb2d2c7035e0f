#pragma once
// A constitutive model that refuses every strain increment: for the tests of the errors that the
// code calling a model (element drivers, the MPM solver) raises when an update fails.
#include <string>
#include <utility>

#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm::test_support {

/// Refuses every update with `message` (a static text, as the models' messages are); its tangent is
/// the identity and its wave modulus the given one [Pa] (what the time step needs).
class RefusingModel final : public ConstitutiveModel {
 public:
  RefusingModel(std::string name, const char* message, double wave_modulus)
      : name_(std::move(name)), message_(message), wave_modulus_(wave_modulus) {}
  std::string name() const override { return name_; }
  UpdateResult update(MaterialState&, const Vec6&) const override {
    UpdateResult result;
    result.ok = false;
    result.message = message_;
    return result;
  }
  Mat6 tangent(const MaterialState&, const Vec6&) const override { return Mat6::Identity(); }
  double wave_modulus(const MaterialState&) const override { return wave_modulus_; }

 private:
  std::string name_;
  const char* message_;
  double wave_modulus_;
};

}  // namespace pilempm::test_support
