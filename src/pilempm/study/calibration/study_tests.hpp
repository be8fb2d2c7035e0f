#pragma once
// The element tests of the calibration study by name (examples/study_calibration.toml) and the
// constants of its items: the study finds its series in the case by these names.
#include <string>
#include <utility>
#include <vector>

namespace pilempm::study::calibration {

inline constexpr double kKPa = 1.0e3;
inline constexpr double kMPa = 1.0e6;

// Item 1: oedometer curves of two sets, five initial void ratios each.
inline const std::vector<std::string> kOedometerSets = {"original", "loose-fit"};
inline const std::vector<std::string> kOedometerE0 = {"0.657", "0.70", "0.75", "0.80", "0.823"};
/// e.g. oed-original-e0.657
inline std::string oedometer_name(const std::string& set, const std::string& e0) {
  return "oed-" + set + "-e" + e0;
}
std::vector<std::string> oedometer_names();

// Item 2: the drained triaxial calibration tests.
inline const std::vector<std::string> kTriaxialDense = {
    "tx-dense-s3-50kPa-e0.59", "tx-dense-s3-100kPa-e0.60", "tx-dense-s3-200kPa-e0.60"};
inline const std::vector<std::string> kTriaxialLoose = {
    "tx-loose-s3-50kPa-e0.70", "tx-loose-s3-100kPa-e0.84", "tx-loose-s3-200kPa-e0.81"};
inline const std::vector<std::string> kTriaxialDeltares = {"tx-s3-200kPa-e0.67",
                                                           "tx-s3-200kPa-e0.75"};

// Item 3: cyclic oedometer with each intergranular strain set and without.
inline const std::vector<std::string> kCyclic = {"oed-cyclic-IGS1", "oed-cyclic-IGS2",
                                                 "oed-cyclic-IGS3", "oed-cyclic-IGS4",
                                                 "oed-cyclic-no-IGS"};
inline const std::string kCyclicReference = "oed-cyclic-no-IGS";

// Item 4: high-pressure triaxial; Bolton's table of the study (docs/study.md): R_D = 95 % of
// the series, phi_c of the original set.
inline const std::vector<std::string> kHighPressure = {"tx-hp-s3-0.5MPa", "tx-hp-s3-2MPa",
                                                       "tx-hp-s3-4MPa",   "tx-hp-s3-6MPa",
                                                       "tx-hp-s3-16MPa",  "tx-hp-s3-30MPa"};
inline constexpr double kBoltonRelativeDensity = 0.95;
inline constexpr double kBoltonPhiC = 31.0;

// Item 5: alpha(p) at the void ratios of the study, and the pressures of its README table.
inline const std::vector<double> kAlphaVoidRatios = {0.68, 0.75};
inline const std::vector<double> kAlphaTablePressuresKPa = {10,   20,   50,   100,   200,   500,
                                                            1000, 2000, 5000, 10000, 20000, 30000};

// Item 6: triaxial at 6 MPa for several alpha (0.12 is the high-pressure series' own test).
inline const std::vector<std::string> kAlphaSensitivity = {
    "tx-alpha0.03-s3-6MPa", "tx-alpha0.06-s3-6MPa", "tx-hp-s3-6MPa", "tx-alpha0.2-s3-6MPa"};

// Items 7 and 8: {low pressure, high pressure} of each set.
inline const std::pair<std::string, std::string> kOriginal = {"tx-original-s3-0.1MPa-e0.68",
                                                              "tx-original-s3-10MPa-e0.68"};
inline const std::pair<std::string, std::string> kModified = {"tx-modified-s3-0.1MPa-e0.68",
                                                              "tx-modified-s3-10MPa-e0.68"};
inline const std::pair<std::string, std::string> kStressDependent = {
    "tx-stress-dependent-s3-0.1MPa-e0.68", "tx-stress-dependent-s3-10MPa-e0.68"};
/// The stress-dependent alpha option should match the sets within this [deg].
inline constexpr double kStressDependentTolerance = 1.0;

/// Every test of the study, each once, in the order the study runs them.
std::vector<std::string> study_test_names();

}  // namespace pilempm::study::calibration
