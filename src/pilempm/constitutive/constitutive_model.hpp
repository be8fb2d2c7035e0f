#pragma once
// The one interface through which every consumer (element tests, MPM, calibration, benchmarks)
// calls a constitutive model. A model knows nothing of grids, particles or files.
#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pilempm/constitutive/material_state.hpp"

namespace pilempm {

/// What happened during one stress update. A failed update leaves the state unchanged.
struct UpdateResult {
  bool ok = true;
  int substeps = 0;                ///< accepted sub-steps of the integrator
  int rejected_substeps = 0;       ///< sub-steps rejected by the error control
  int mean_stress_floor_hits = 0;  ///< times the stress was set to the floor p_min (see model doc)
  double void_ratio_excess = 0.0;  ///< largest relative distance e left its band before clamping
  /// The update returned the stress to an apex of the yield surface (Mohr-Coulomb's, or its
  /// tension cut-off's), where the stress no longer changes with the strain.
  bool at_apex = false;
  const char* message = "";  ///< why it failed (static text), empty when ok
};

/// The sub-steps an update by sub-stepping took (the accepted steps of its integrator, as fractions
/// of the increment), so that the update of a nearby increment can take the very same ones
/// (ConstitutiveModel::update_along). A finite-difference tangent of the integrated update needs
/// this: two adaptive integrations of nearly the same increment can choose different sub-steps,
/// and their difference is then of the order of the integrator's tolerance, not of the
/// perturbation; along one path the difference quotient is the derivative of one smooth map.
struct SubstepPath {
  /// The most runs of equal sub-steps a path holds (the sub-steps an integrator's stability limit
  /// caps are equal: a long path has few runs).
  static constexpr int kCapacity = 24;
  /// Whether the runs hold the whole path: false for a model that does not sub-step, an update
  /// that reached the edge of the model's domain (its path is not smooth there) or a path of more
  /// than kCapacity runs.
  bool replayable = false;
  int runs = 0;
  std::array<double, kCapacity> step{};  ///< run r: `repeat[r]` sub-steps of `step[r]` each
  std::array<int, kCapacity> repeat{};

  void clear() {
    replayable = false;
    runs = 0;
  }
  /// Appends a sub-step (not replayable once the runs are full).
  void append(double h) {
    if (runs > 0 && step[std::size_t(runs - 1)] == h) {
      ++repeat[std::size_t(runs - 1)];
    } else if (runs < kCapacity) {
      step[std::size_t(runs)] = h;
      repeat[std::size_t(runs++)] = 1;
    } else {
      replayable = false;
    }
  }
  /// The number of sub-steps.
  int substeps() const {
    int n = 0;
    for (int r = 0; r < runs; ++r) n += repeat[std::size_t(r)];
    return n;
  }
};

/// A constitutive model: parameters in, and a pure function from (state, strain increment) to the
/// new state. Implementations are immutable after construction and safe to call from many threads.
class ConstitutiveModel {
 public:
  virtual ~ConstitutiveModel() = default;

  /// Short name for messages and output, e.g. "hypoplastic+IGS".
  virtual std::string name() const = 0;

  /// Advances the state by a small-strain increment (Mandel, tension positive). Objective
  /// rotation of the stress by the spin is the caller's job (see objective_rotation.hpp), so the
  /// same code serves the element tests (no spin) and the MPM solver.
  virtual UpdateResult update(MaterialState& state, const Vec6& strain_increment) const = 0;

  /// update() that also records in `path` the sub-steps it took (SubstepPath). By default, for
  /// models that do not sub-step: update(), and the path is not replayable.
  virtual UpdateResult update_recording(MaterialState& state, const Vec6& strain_increment,
                                        SubstepPath& path) const {
    path.clear();
    return update(state, strain_increment);
  }

  /// The update taking the sub-steps of `path` without error control where the path is
  /// replayable and stays inside the model's domain, else update(). By default update().
  virtual UpdateResult update_along(MaterialState& state, const Vec6& strain_increment,
                                    const SubstepPath& path) const {
    (void)path;
    return update(state, strain_increment);
  }

  /// Tangent d(stress rate)/d(strain rate) at the state for a strain rate in the given direction
  /// (rate-independent models with a direction-dependent tangent need the direction).
  virtual Mat6 tangent(const MaterialState& state, const Vec6& strain_direction) const = 0;

  /// The derivative of update(state, strain_increment)'s stress with respect to the increment
  /// (the consistent tangent of the integrated update, Mandel) into `tangent`, where the model
  /// has it in closed form; false where it has not, and the caller differentiates the update
  /// (the quasi-static analysis's Newton matrix). None by default.
  virtual bool consistent_tangent(const MaterialState& state, const Vec6& strain_increment,
                                  Mat6& tangent) const {
    (void)state;
    (void)strain_increment;
    (void)tangent;
    return false;
  }

  /// Upper bound of the constrained (P-wave) modulus at the state [Pa], for the critical time step.
  virtual double wave_modulus(const MaterialState& state) const = 0;

  /// The model's history variables in MaterialState::history: what a checkpoint stores and what
  /// an objective update rotates (tensors). Slots not listed stay zero. None by default.
  virtual std::span<const HistoryVariable> history_variables() const { return {}; }

  /// Scalar results per point for output (e.g. VTU point data), by name; none by default.
  virtual std::vector<std::string> output_fields() const { return {}; }
  /// The value of output field `index` (into output_fields()) at the state.
  virtual double output_field(std::size_t index, const MaterialState& state) const {
    (void)index;
    (void)state;
    return 0.0;
  }
};

/// Rotates every tensor among the model's history variables by R (R A R^T, Mandel), with
/// `rotate` a callable rotate(Vec6&): the objective part of an update for the history.
template <class Rotate>
void rotate_history_tensors(std::span<const HistoryVariable> variables, MaterialState& state,
                            Rotate&& rotate) {
  for (const HistoryVariable& v : variables) {
    if (!v.tensor) continue;
    Vec6 tensor = Eigen::Map<const Vec6>(state.history.data() + v.offset);
    rotate(tensor);
    Eigen::Map<Vec6>(state.history.data() + v.offset) = tensor;
  }
}

using ModelPtr = std::shared_ptr<const ConstitutiveModel>;

}  // namespace pilempm
