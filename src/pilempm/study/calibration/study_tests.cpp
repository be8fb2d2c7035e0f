#include "pilempm/study/calibration/study_tests.hpp"

#include <algorithm>

namespace pilempm::study::calibration {

std::vector<std::string> oedometer_names() {
  std::vector<std::string> names;
  for (const auto& set : kOedometerSets)
    for (const auto& e0 : kOedometerE0) names.push_back(oedometer_name(set, e0));
  return names;
}

std::vector<std::string> study_test_names() {
  std::vector<std::string> names = oedometer_names();
  for (const auto* list : {&kCyclic, &kTriaxialDense, &kTriaxialLoose, &kTriaxialDeltares,
                           &kHighPressure, &kAlphaSensitivity})
    for (const std::string& name : *list)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  for (const auto& pair : {kModified, kOriginal, kStressDependent}) {
    names.push_back(pair.second);
    names.push_back(pair.first);
  }
  return names;
}

}  // namespace pilempm::study::calibration
