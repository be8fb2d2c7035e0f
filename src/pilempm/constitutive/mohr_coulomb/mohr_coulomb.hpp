#pragma once
// Linear elastic - perfectly plastic Mohr-Coulomb model with a non-associated plastic potential
// (dilatancy angle psi) and an optional Rankine tension cut-off, integrated by an exact return
// mapping in principal stress space. The baseline model of docs/model.md §2-§6 (end) and the model
// for MPM verification.
//
// Conventions: tension positive; principal stresses sorted s1 >= s2 >= s3, so s3 is the major
// compression. In that sextant the yield functions are (k = (1 + sin phi)/(1 - sin phi),
// sigma_c = 2 c cos phi / (1 - sin phi) = 2 c sqrt(k), the uniaxial compressive strength)
//   f  = k s1 - s3 - sigma_c       (<=> (s1 - s3) + (s1 + s3) sin phi - 2 c cos phi <= 0, scaled)
//   ft = s1 - t                    (Rankine tension cut-off, t = tension cut-off)
// and the plastic potentials g = m s1 - s3 (m = (1 + sin psi)/(1 - sin psi)) and gt = s1.
//
// Algorithm (after Clausen, Damkilde & Andersen, Int. J. Numer. Meth. Eng. 66 (2006) and Comput.
// Struct. 85 (2007), and de Souza Neto, Peric & Owen 2008, ch. 8; written from the theory): elastic
// predictor, spectral decomposition of the trial stress, exact return of the sorted principal trial
// stress onto the polyhedral yield surface. Because the surfaces are planes in principal space and
// the elastic stiffness is constant, every return is a closed-form linear solve. The candidate
// returns, each accepted only when its plastic multipliers are >= 0 and the returned point
// satisfies every yield function of the sextant:
//   Mohr-Coulomb plane; triaxial-compression edge (s1 = s2); triaxial-extension edge (s2 = s3);
//   tension plane (s1 = t); tension edge (s1 = s2 = t); the line where the Mohr-Coulomb plane
//   meets the tension plane; the corners (t, t, k t - sigma_c) and (t, k t - sigma_c, k t -
//   sigma_c); the tension apex (t, t, t); and, without an effective cut-off, the Mohr-Coulomb apex
//   c cot(phi) (1, 1, 1).
// The Mohr-Coulomb apex is taken for every trial stress that no other return accepts. For psi > 0
// that set is the apex plus D times the cone of the six potential gradients, so the apex return
// obeys the flow rule too. For psi = 0 the potential has no volumetric part and cannot reach the
// apex: every trial stress with a mean stress beyond c cot(phi) goes to the apex, with a
// volumetric plastic strain (the usual convention, e.g. de Souza Neto et al.). The new stress has
// the eigenvectors of the trial stress.
//
// State: the accumulated plastic shear strain is the sum of sqrt(2/3) ||dev(d eps_p)|| (the
// triaxial shear strain measure, conjugate to q); the void ratio follows de = (1 + e) tr(d eps).
#include <limits>
#include <string>

#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm {

struct MohrCoulombParameters {
  double young_modulus = 0.0;        ///< E [Pa], > 0
  double poisson_ratio = 0.0;        ///< nu [-], in (-1, 0.5)
  double cohesion = 0.0;             ///< c [Pa], >= 0 (> 0 when friction_angle_deg = 0)
  double friction_angle_deg = 0.0;   ///< phi [deg], in [0, 90)
  double dilatancy_angle_deg = 0.0;  ///< psi [deg], in [0, phi]
  /// Largest tensile principal stress t [Pa]. The default, +infinity, means no cut-off beyond the
  /// Mohr-Coulomb surface itself, whose apex c cot(phi) then bounds the tension (for phi = 0 the
  /// tension is unbounded). A finite value must be in [0, c cot(phi)]; the apex value itself is the
  /// same as no cut-off.
  double tension_cutoff = std::numeric_limits<double>::infinity();

  /// Throws InvalidValue naming the first impossible value and its allowed range.
  void validate() const;

  double shear_modulus() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double bulk_modulus() const { return young_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)); }
  /// The apex c cot(phi) [Pa] (tension positive); +infinity for phi = 0.
  double apex_stress() const;
};

class MohrCoulomb final : public ConstitutiveModel {
 public:
  /// Which return the trial stress took.
  enum class ReturnRegion {
    elastic,
    plane,                       ///< Mohr-Coulomb plane
    compression_edge,            ///< Mohr-Coulomb edge s1 = s2 (triaxial compression)
    extension_edge,              ///< Mohr-Coulomb edge s2 = s3 (triaxial extension)
    apex,                        ///< Mohr-Coulomb apex c cot(phi) (1, 1, 1)
    tension_plane,               ///< s1 = t
    tension_edge,                ///< s1 = s2 = t
    tension_apex,                ///< s1 = s2 = s3 = t
    plane_tension_line,          ///< Mohr-Coulomb plane and s1 = t
    compression_tension_corner,  ///< (t, t, k t - sigma_c)
    extension_tension_corner,    ///< (t, k t - sigma_c, k t - sigma_c)
  };

  /// The return of a sorted principal trial stress.
  struct PrincipalReturn {
    Vec3 stress = Vec3::Zero();  ///< returned principal stresses, same order as the trial
    ReturnRegion region = ReturnRegion::elastic;
    /// The planes the returned stress lies on (bit i: plane i of f(1,3), f(2,3), f(1,2), ft(1),
    /// ft(2), ft(3)); 0 for an elastic trial.
    unsigned active = 0;
    /// False only if no candidate return passed its checks (not expected; the one with the
    /// smallest violation was taken).
    bool consistent = true;
  };

  explicit MohrCoulomb(const MohrCoulombParameters& parameters);

  std::string name() const override { return "mohr-coulomb"; }
  UpdateResult update(MaterialState& state, const Vec6& strain_increment) const override;
  /// The elastic stiffness, whatever the state and direction (not the elastoplastic tangent: the
  /// callers use it as a first guess and for the time step, where the elastic one is the bound).
  Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const override;
  /// The consistent tangent of update(): the elastic stiffness, then the derivative of the return
  /// in principal space (I − D B (Aᵀ D B)⁻¹ Aᵀ on the active planes A with flows B, 0 at a
  /// corner or apex), turned into the general space with the spin of the eigenvectors (the
  /// isotropic tensor function's derivative; de Souza Neto, Perić & Owen 2008, Computational
  /// Methods for Plasticity, §8.3 and appendix A). False where the return found no consistent
  /// candidate.
  bool consistent_tangent(const MaterialState& state, const Vec6& strain_increment,
                          Mat6& tangent) const override;
  /// K + 4G/3.
  double wave_modulus(const MaterialState& state) const override;
  /// "plastic_shear_strain" (a scalar).
  std::span<const HistoryVariable> history_variables() const override;

  /// The accumulated plastic shear strain in a state's history [-].
  static double& plastic_shear_strain(MaterialState& state) { return state.history[0]; }
  static double plastic_shear_strain(const MaterialState& state) { return state.history[0]; }

  /// Exact return of principal trial stresses sorted s1 >= s2 >= s3.
  PrincipalReturn return_principal(const Vec3& sorted_trial) const;

  /// (s1 - s3) + (s1 + s3) sin phi - 2 c cos phi [Pa]: <= 0 inside the Mohr-Coulomb surface.
  double mohr_coulomb_function(const Vec6& stress) const;
  /// s1 - t [Pa] with the effective cut-off; -infinity without one.
  double tension_function(const Vec6& stress) const;

  const MohrCoulombParameters& parameters() const { return parameters_; }
  /// The tension cut-off in use: min(t, c cot phi), +infinity when there is none.
  double effective_tension_cutoff() const { return tension_cutoff_; }
  bool has_tension_cutoff() const { return cutoff_active_; }

 private:
  struct Plane {
    Vec3 normal;          // gradient of the yield function
    Vec3 flow;            // gradient of the plastic potential
    Vec3 stiffness_flow;  // D_p * flow, D_p the principal elastic stiffness
    double level = 0.0;   // f = normal . s - level
  };
  static constexpr int kPlanes = 6;  // f(1,3), f(2,3), f(1,2), ft(1), ft(2), ft(3)

  double yield_value(int plane, const Vec3& s) const;
  double violation(const Vec3& returned, unsigned active, double scale) const;
  double cone_violation(const Vec3& difference, const int* planes, int count, double scale) const;

  MohrCoulombParameters parameters_;
  Mat6 stiffness_;
  double bulk_ = 0.0, shear_ = 0.0;
  double k_ = 1.0;               // (1 + sin phi)/(1 - sin phi)
  double strength_ = 0.0;        // sigma_c = 2 c cos phi / (1 - sin phi)
  double apex_ = 0.0;            // c cot phi, +inf for phi = 0
  double tension_cutoff_ = 0.0;  // effective cut-off
  bool cutoff_active_ = false;   // t < apex
  Plane planes_[kPlanes];
};

}  // namespace pilempm
