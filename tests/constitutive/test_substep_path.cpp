// The recorded sub-steps of an update (SubstepPath) and the update along them: the replay of the
// recorded path reproduces the adaptive update to the last bit, a path that reached the edge of
// the model's domain or has too many runs is not replayed, and the forward-difference tangent along
// one path is the derivative of a smooth map (two perturbation sizes agree) and agrees with the
// derivative of the adaptive update to the integrator's tolerance.
#include <gtest/gtest.h>

#include <array>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/constitutive/mohr_coulomb/mohr_coulomb.hpp"

namespace pilempm {
namespace {

using Scheme = IntegratorSettings::Scheme;

MaterialState sand_state() {
  MaterialState state;
  state.stress << -150e3, -100e3, -80e3, 0.0, 0.0, kSqrt2 * 20e3;
  state.void_ratio = 0.68;
  return state;
}

Hypoplastic sand(Scheme scheme, int fixed_substeps = 0) {
  IntegratorSettings settings;
  settings.scheme = scheme;
  settings.fixed_substeps = fixed_substeps;
  return Hypoplastic(hypoplastic_set("original"), intergranular_strain_set("IGS3"), settings);
}

// Increments of a load step of the quasi-static analysis: 0.01 % to 2 %, in compression, shear
// and extension, with a mobilised intergranular strain in the start state for some.
struct Case {
  Vec6 increment;
  bool reversal;  // the intergranular strain set opposite to the increment first
};
std::array<Case, 4> cases() {
  Vec6 compression, shear, extension, mixed;
  compression << -1e-4, 0.2e-4, 0.1e-4, 0.0, 0.0, 0.3e-4;
  shear << 0.0, 0.0, 0.0, 0.0, 0.0, 5e-3;
  extension << 2e-3, -1e-3, 0.0, 0.0, 0.0, 0.0;
  mixed << -2e-2, 4e-3, 3e-3, 0.0, 0.0, 6e-3;
  return {Case{compression, false}, Case{shear, true}, Case{extension, false}, Case{mixed, true}};
}

MaterialState start_for(const Case& c) {
  MaterialState state = sand_state();
  if (c.reversal) Hypoplastic::intergranular_strain(state) = -0.8e-4 * c.increment.normalized();
  return state;
}

TEST(SubstepPath, ReplayingTheRecordedPathGivesTheAdaptiveEndPointToTheLastBit) {
  for (Scheme scheme : {Scheme::heun_euler, Scheme::bogacki_shampine})
    for (const Case& c : cases()) {
      const Hypoplastic model = sand(scheme);
      MaterialState adaptive = start_for(c), recorded = start_for(c), replayed = start_for(c);
      const UpdateResult plain = model.update(adaptive, c.increment);
      SubstepPath path;
      const UpdateResult recording = model.update_recording(recorded, c.increment, path);
      ASSERT_TRUE(plain.ok && recording.ok);
      // Heun-Euler's error control varies every sub-step: its longer paths have too many runs.
      if (scheme == Scheme::heun_euler && !path.replayable) {
        EXPECT_GT(recording.substeps, SubstepPath::kCapacity);
        continue;
      }
      ASSERT_TRUE(path.replayable);
      EXPECT_EQ(path.substeps(), recording.substeps);
      double sum = 0.0;
      for (int r = 0; r < path.runs; ++r)
        sum += path.repeat[std::size_t(r)] * path.step[std::size_t(r)];
      EXPECT_NEAR(sum, 1.0, 1e-14);
      const UpdateResult along = model.update_along(replayed, c.increment, path);
      ASSERT_TRUE(along.ok);
      EXPECT_EQ(along.substeps, path.substeps());
      EXPECT_EQ(along.rejected_substeps, 0);
      for (const MaterialState* s : {&recorded, &replayed}) {
        EXPECT_TRUE(s->stress == adaptive.stress);
        EXPECT_EQ(s->void_ratio, adaptive.void_ratio);
        EXPECT_TRUE(s->history == adaptive.history);
      }
    }
}

// A path through the tension cut-off (sand pulled apart sideways while it carries load
// vertically, docs/model.md §5) is replayable, and its replay reproduces it to the last bit.
TEST(SubstepPath, APathThroughTheTensionCutOffIsReplayedToTheLastBit) {
  for (Scheme scheme : {Scheme::heun_euler, Scheme::bogacki_shampine}) {
    const Hypoplastic model = sand(scheme);
    MaterialState start;
    start.stress = diagonal6(-20.0, -3000.0, -1200.0);
    start.void_ratio = 0.68;
    const Vec6 increment = diagonal6(4.0e-5, -1.0e-5, 0.0);
    MaterialState recorded = start, replayed = start;
    SubstepPath path;
    const UpdateResult recording = model.update_recording(recorded, increment, path);
    ASSERT_TRUE(recording.ok) << recording.message;
    EXPECT_EQ(recording.mean_stress_floor_hits, 0);
    EXPECT_GT(principal_values(recorded.stress).maxCoeff(), -1.5);  // on the cut-off
    ASSERT_TRUE(path.replayable);
    const UpdateResult along = model.update_along(replayed, increment, path);
    ASSERT_TRUE(along.ok);
    EXPECT_EQ(along.substeps, path.substeps());
    EXPECT_TRUE(replayed.stress == recorded.stress);
    EXPECT_EQ(replayed.void_ratio, recorded.void_ratio);
    EXPECT_TRUE(replayed.history == recorded.history);
  }
}

TEST(SubstepPath, APathThatReachedTheFloorOrHasTooManyRunsIsNotReplayed) {
  const Hypoplastic model = sand(Scheme::bogacki_shampine);
  // Extension of 5 %: the sand comes apart and its stress reaches the floor.
  Vec6 apart = Vec6::Zero();
  apart[k11] = apart[k22] = apart[k33] = 0.05;
  MaterialState state = sand_state(), adaptive = sand_state();
  SubstepPath path;
  const UpdateResult floor = model.update_recording(state, apart, path);
  ASSERT_TRUE(floor.ok);
  ASSERT_GT(floor.mean_stress_floor_hits, 0);
  EXPECT_FALSE(path.replayable);
  // update_along then integrates adaptively: the same as update().
  MaterialState fallback = sand_state();
  ASSERT_TRUE(model.update_along(fallback, apart, path).ok);
  ASSERT_TRUE(model.update(adaptive, apart).ok);
  EXPECT_TRUE(fallback.stress == adaptive.stress);

  // Runs: equal sub-steps extend a run; a path of more runs than kCapacity is not replayable.
  SubstepPath runs;
  runs.replayable = true;
  for (int r = 0; r < SubstepPath::kCapacity; ++r) {
    runs.append(1.0 / (r + 2));
    runs.append(1.0 / (r + 2));
  }
  EXPECT_TRUE(runs.replayable);
  EXPECT_EQ(runs.runs, SubstepPath::kCapacity);
  EXPECT_EQ(runs.substeps(), 2 * SubstepPath::kCapacity);
  runs.append(1.0);
  EXPECT_FALSE(runs.replayable);

  const Vec6 increment = cases()[0].increment;
  // A model that does not sub-step records nothing replayable and updates as update() does.
  const MohrCoulomb mc(MohrCoulombParameters{50e6, 0.3, 0.0, 33.0, 5.0});
  SubstepPath none;
  MaterialState m1 = sand_state(), m2 = sand_state();
  ASSERT_TRUE(mc.update_recording(m1, increment, none).ok);
  ASSERT_TRUE(mc.update(m2, increment).ok);
  EXPECT_FALSE(none.replayable);
  EXPECT_TRUE(m1.stress == m2.stress);
}

// d(stress)/d(increment) by forward differences, column j = (T(Δε + h e_j) − T(Δε)) / h, the
// probes along `path` (or adaptive when it is not replayable).
Mat6 difference_tangent(const Hypoplastic& model, const MaterialState& start, const Vec6& increment,
                        const SubstepPath& path, double relative_h) {
  MaterialState base = start;
  EXPECT_TRUE(model.update_along(base, increment, path).ok);
  const double h = relative_h * increment.norm();
  Mat6 tangent;
  for (int j = 0; j < 6; ++j) {
    Vec6 perturbed = increment;
    perturbed[j] += h;
    MaterialState probe = start;
    EXPECT_TRUE(model.update_along(probe, perturbed, path).ok);
    tangent.col(j) = (probe.stress - base.stress) / h;
  }
  return tangent;
}

TEST(SubstepPath, TheTangentAlongOnePathIsTheDerivativeOfASmoothMap) {
  for (const Case& c : cases()) {
    const Hypoplastic model = sand(Scheme::bogacki_shampine);
    const MaterialState start = start_for(c);
    MaterialState end = start;
    SubstepPath path;
    ASSERT_TRUE(model.update_recording(end, c.increment, path).ok);
    ASSERT_TRUE(path.replayable);
    // Every sub-step inside Bogacki-Shampine's stability interval for the intergranular strain's
    // decay rate ||D|| / R (IGS3: beta_r = 1, R = 1e-4).
    for (int r = 0; r < path.runs; ++r)
      EXPECT_LE(path.step[std::size_t(r)] * c.increment.norm() / 1e-4,
                kStabilityFraction * 2.51 * (1.0 + 1e-12));
    const Mat6 fine = difference_tangent(model, start, c.increment, path, 1e-7);
    const Mat6 coarse = difference_tangent(model, start, c.increment, path, 1e-5);
    // Along one path the map is smooth: the forward difference changes by O(h).
    EXPECT_LT((fine - coarse).norm(), 1e-4 * fine.norm());
    // The sub-steps of the adaptive update depend on the increment only through its error
    // estimate: the derivative along the path is that of the adaptive update to about the
    // integrator's tolerance (10^-3), measured with a central difference of the adaptive update
    // over a span large against the changes of its sub-steps.
    Mat6 central;
    const double h = 1e-3 * c.increment.norm();
    for (int j = 0; j < 6; ++j) {
      MaterialState plus = start, minus = start;
      Vec6 up = c.increment, down = c.increment;
      up[j] += h;
      down[j] -= h;
      ASSERT_TRUE(model.update(plus, up).ok && model.update(minus, down).ok);
      central.col(j) = (plus.stress - minus.stress) / (2.0 * h);
    }
    EXPECT_LT((fine - central).norm(), 2e-2 * central.norm());
  }
}

}  // namespace
}  // namespace pilempm
