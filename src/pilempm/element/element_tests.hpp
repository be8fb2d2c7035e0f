#pragma once
// The element-test types of docs/study.md §2, each a loading programme for the mixed-control
// driver: isotropic compression, oedometer (monotonic and cyclic between stress targets), drained
// triaxial compression at constant cell pressure, undrained (constant-volume) triaxial, and a
// user-given strain path. Axial is Mandel component 11, radial are 22 and 33.
//
// Everything here is SI and tension positive; the curves (CurvePoint) are compression positive,
// the convention of the laboratory.
#include <functional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"

namespace pilempm {

/// How the point starts.
struct InitialCondition {
  double e0 = 0.7;  ///< initial void ratio, in the convention below
  VoidRatioConvention e0_at = VoidRatioConvention::at_initial_stress;
  /// Intergranular strain at the start: fully mobilised by the isotropic compression that made
  /// the sample (delta = -R I/sqrt3, rho = 1), zero (rho = 0, the stiffest start), fully
  /// mobilised along the first strain increment of the test (delta = R de/||de||, e.g. axial in
  /// an oedometer, the start of the soilmodels.info UMAT driver and of PLAXIS' element tests),
  /// or the tensor `igs_tensor`.
  enum class Igs { compression, zero, first_increment, tensor } igs = Igs::compression;
  Vec6 igs_tensor = Vec6::Zero();  ///< Mandel, tension positive; ||delta|| <= R
};

/// "compression", "zero", "first-increment", "tensor".
std::string_view to_string(InitialCondition::Igs igs);

struct IsotropicCompressionTest {
  double p0 = 10e3;     ///< start [Pa]
  double p_end = 30e6;  ///< end [Pa]
  int steps = 400;      ///< increments, geometric in p
};

struct OedometerTest {
  double sigma_v0 = 10e3;  ///< initial vertical stress [Pa]; sigma_h0 = K0 sigma_v0
  double K0 = 0.5;         ///< initial lateral stress ratio
  /// Vertical stress targets [Pa], visited in order: one entry is a monotonic test, several
  /// entries (e.g. 400, 100, 400, 100 kPa) a cyclic one.
  std::vector<double> sigma_v_targets = {400e3};
  int steps_per_segment = 200;
};

struct DrainedTriaxialTest {
  double sigma3 = 100e3;      ///< cell pressure [Pa], also the isotropic initial stress
  double axial_strain = 0.2;  ///< final axial strain (compression positive) [-]
  int steps = 2000;
};

struct UndrainedTriaxialTest {
  double p0 = 100e3;          ///< isotropic consolidation stress [Pa]
  double axial_strain = 0.1;  ///< final axial strain (compression positive) [-]
  int steps = 2000;
};

/// A strain path from an initial stress: segments of a total strain increment (tension
/// positive, Mandel) applied in equal steps.
struct StrainPathTest {
  Vec6 initial_stress = -100e3 * identity6();
  struct Segment {
    Vec6 strain = Vec6::Zero();
    int steps = 100;
  };
  std::vector<Segment> segments;
};

using ElementTest = std::variant<IsotropicCompressionTest, OedometerTest, DrainedTriaxialTest,
                                 UndrainedTriaxialTest, StrainPathTest>;

/// Name of the test type as used in case files ("isotropic", "oedometer", "triaxial",
/// "undrained-triaxial", "strain-path").
std::string test_type_name(const ElementTest& test);

/// One row of a curve, compression positive.
struct CurvePoint {
  double axial_strain;       ///< -eps_11 [-]
  double radial_strain;      ///< -eps_22 [-]
  double volumetric_strain;  ///< -tr eps [-]
  double axial_stress;       ///< -sigma_11 [Pa]
  double radial_stress;      ///< -sigma_22 [Pa]
  double lateral_stress;     ///< -sigma_33 [Pa]
  double p;                  ///< mean stress [Pa]
  double q;                  ///< sigma_a - sigma_r [Pa] (signed: negative in extension)
  double void_ratio;         ///< e [-]
  double phi_mobilised_deg;  ///< asin((s1 - s3)/(s1 + s3)), principal stresses [deg]
  double igs_ratio;          ///< rho = ||delta|| / R, 0 without intergranular strain [-]
  int substeps;              ///< sub-steps the integrator took for this increment
};

/// What a person wants to know about a curve.
struct ElementSummary {
  double initial_void_ratio = 0.0;  ///< the void ratio actually used at the start
  double initial_p = 0.0;           ///< [Pa]
  double peak_q = 0.0;              ///< largest q [Pa]
  double axial_strain_at_peak = 0.0;
  double phi_at_peak_deg = 0.0;          ///< mobilised friction angle at peak q
  double dilatancy_ratio_at_peak = 0.0;  ///< d eps_v / d eps_1 at peak (compression positive)
  double psi_at_peak_deg = 0.0;          ///< sin psi = -(d eps_v/d eps_1) / (2 - d eps_v/d eps_1)
  bool peak_at_end = false;              ///< the largest q is the last point: no peak was reached
  CurvePoint final{};
  long increments = 0;
  long substeps = 0;
  long mean_stress_floor_hits = 0;
  double max_void_ratio_excess = 0.0;
};

struct ElementResult {
  std::vector<CurvePoint> curve;
  ElementSummary summary;
};

/// Called after every increment with (done, total) for progress output; may be empty.
using ProgressCallback = std::function<void(long done, long total)>;

/// The starting state for a given initial stress: void ratio by its convention (Bauer scaling
/// needs the hypoplastic parameters, other models use e0 as it is) and intergranular strain.
MaterialState initial_state(const ConstitutiveModel& model, const Vec6& stress,
                            const InitialCondition& initial);

/// Runs one element test. Throws pilempm::Error (with the increment) when the model fails.
ElementResult run_element_test(const ConstitutiveModel& model, const ElementTest& test,
                               const InitialCondition& initial,
                               const ProgressCallback& progress = {});

/// Throws InvalidValue when a test's settings are impossible (negative stress, zero steps, ...).
void validate(const ElementTest& test);

/// The peak analysis of a curve (exposed for tests and for curves from elsewhere).
ElementSummary summarise(const std::vector<CurvePoint>& curve);

/// Mobilised friction angle of a stress state [deg] from its principal stresses.
double mobilised_friction_angle_deg(const Vec6& stress);

/// Dilatancy angle from d eps_v / d eps_1 (compression positive), Schanz & Vermeer (1996).
double dilatancy_angle_deg(double dilatancy_ratio);

}  // namespace pilempm
