// The explicit integrator of the hypoplastic model: one sub-step of each scheme against the
// scheme written out with Hypoplastic::rate(), the order of accuracy with fixed sub-steps, and
// the convergence of the error-controlled integration as the tolerance shrinks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"

namespace pilempm {
namespace {

using Scheme = IntegratorSettings::Scheme;

double relative_difference(const Vec6& a, const Vec6& b) {
  return (a - b).norm() / b.norm();
}

// A compressive, anisotropic start well inside the void ratio band.
MaterialState start_state() {
  MaterialState state;
  state.stress << -150e3, -100e3, -80e3, kSqrt2 * 8e3, kSqrt2 * -5e3, kSqrt2 * 20e3;
  state.void_ratio = 0.70;
  return state;
}

// A compression-and-shear direction that raises the mean stress (so the path stays far from
// the tensile edge, and without the intergranular strain the rate is smooth along it).
Vec6 loading_direction() {
  Vec6 d;
  d << -1.0, 0.2, 0.1, 0.3, -0.2, 0.25;
  return d.normalized();
}

Hypoplastic make_model(Scheme scheme, double tolerance, int fixed_substeps,
                       const char* igs = "none") {
  IntegratorSettings settings;
  settings.scheme = scheme;
  settings.tolerance = tolerance;
  settings.fixed_substeps = fixed_substeps;
  return Hypoplastic(hypoplastic_set("original"), intergranular_strain_set(igs), settings);
}

MaterialState one_increment(const Hypoplastic& model, const Vec6& increment) {
  MaterialState state = start_state();
  const UpdateResult result = model.update(state, increment);
  EXPECT_TRUE(result.ok) << result.message;
  return state;
}

TEST(HypoplasticIntegrator, OneSubStepIsTheSchemeWrittenOut) {
  const Vec6 D = 2e-3 * loading_direction();
  const MaterialState y = start_state();
  auto shifted = [&](const MaterialState& base, double h, const Hypoplastic::Rate& k) {
    MaterialState s = base;
    s.stress += h * k.stress;
    s.void_ratio += h * k.void_ratio;
    Hypoplastic::intergranular_strain(s) += h * k.intergranular_strain;
    return s;
  };
  {
    const Hypoplastic model = make_model(Scheme::heun_euler, 1e-3, 1);
    const auto k1 = model.rate(y, D);
    const auto k2 = model.rate(shifted(y, 1.0, k1), D);
    const MaterialState expected = shifted(shifted(y, 0.5, k1), 0.5, k2);
    MaterialState actual = y;
    const UpdateResult result = model.update(actual, D);
    EXPECT_TRUE(result.ok);
    EXPECT_EQ(result.substeps, 1);
    EXPECT_EQ(result.rejected_substeps, 0);
    EXPECT_LT(relative_difference(actual.stress, expected.stress), 1e-14);
    EXPECT_NEAR(actual.void_ratio, expected.void_ratio, 1e-15);
  }
  {
    const Hypoplastic model = make_model(Scheme::bogacki_shampine, 1e-3, 1);
    // Bogacki & Shampine (1989): c = (0, 1/2, 3/4), b = (2/9, 1/3, 4/9).
    const auto k1 = model.rate(y, D);
    const auto k2 = model.rate(shifted(y, 0.5, k1), D);
    const auto k3 = model.rate(shifted(y, 0.75, k2), D);
    const MaterialState expected =
        shifted(shifted(shifted(y, 2.0 / 9.0, k1), 1.0 / 3.0, k2), 4.0 / 9.0, k3);
    MaterialState actual = y;
    const UpdateResult result = model.update(actual, D);
    EXPECT_TRUE(result.ok);
    EXPECT_EQ(result.substeps, 1);
    EXPECT_LT(relative_difference(actual.stress, expected.stress), 1e-14);
    EXPECT_NEAR(actual.void_ratio, expected.void_ratio, 1e-15);
  }
  // A zero increment changes nothing.
  const Hypoplastic model = make_model(Scheme::bogacki_shampine, 1e-3, 0, "IGS3");
  MaterialState state = start_state();
  Hypoplastic::intergranular_strain(state) = -0.5e-4 * identity6() / kSqrt3;
  const MaterialState before = state;
  EXPECT_TRUE(model.update(state, Vec6::Zero()).ok);
  EXPECT_EQ(state.stress, before.stress);
  EXPECT_EQ(state.void_ratio, before.void_ratio);
  EXPECT_EQ(Hypoplastic::intergranular_strain(state), Hypoplastic::intergranular_strain(before));
}

TEST(HypoplasticIntegrator, FixedSubStepsConvergeWithTheOrderOfTheScheme) {
  // One large increment (5e-3) on a smooth path without the intergranular strain, integrated with
  // N, 2N, 4N equal sub-steps; the observed order log2(|y_N - y_2N| / |y_2N - y_4N|).
  const Vec6 D = 5e-3 * loading_direction();
  struct Case {
    Scheme scheme;
    double order;
    int N;
  };
  for (const Case c :
       {Case{Scheme::heun_euler, 2.0, 8}, Case{Scheme::bogacki_shampine, 3.0, 8},
        Case{Scheme::heun_euler, 2.0, 32}, Case{Scheme::bogacki_shampine, 3.0, 32}}) {
    SCOPED_TRACE(std::string(to_string(c.scheme)) + " N = " + std::to_string(c.N));
    const Hypoplastic reference_model = make_model(Scheme::bogacki_shampine, 1e-3, 4096);
    const MaterialState reference = one_increment(reference_model, D);
    std::vector<MaterialState> results;
    for (int n : {c.N, 2 * c.N, 4 * c.N})
      results.push_back(one_increment(make_model(c.scheme, 1e-3, n), D));
    const double d1 = (results[0].stress - results[1].stress).norm();
    const double d2 = (results[1].stress - results[2].stress).norm();
    const double observed = std::log2(d1 / d2);
    const double e1 = relative_difference(results[0].stress, reference.stress);
    const double e2 = relative_difference(results[1].stress, reference.stress);
    const double e3 = relative_difference(results[2].stress, reference.stress);
    const double observed_vs_reference = std::log2(e2 / e3);
    std::printf(
        "[ measured ] %s, N = %d/%d/%d: errors vs reference %.3e %.3e %.3e, order (Richardson) "
        "%.3f, order (vs reference, 2N/4N) %.3f\n",
        std::string(to_string(c.scheme)).c_str(), c.N, 2 * c.N, 4 * c.N, e1, e2, e3, observed,
        observed_vs_reference);
    EXPECT_NEAR(observed, c.order, 0.3);
    EXPECT_NEAR(observed_vs_reference, c.order, 0.3);
    EXPECT_GT(e3, 1e-14);  // well above round-off, so the order is meaningful
  }
}

// A strain path of several increments: loading, partial unloading, reloading in another direction.
std::vector<Vec6> strain_path() {
  std::vector<Vec6> path;
  Vec6 other;
  other << -0.3, -0.6, 0.4, -0.2, 0.1, 0.0;
  for (int i = 0; i < 4; ++i) path.push_back(5e-3 * loading_direction());
  for (int i = 0; i < 2; ++i) path.push_back(-1e-3 * loading_direction());
  for (int i = 0; i < 4; ++i) path.push_back(5e-3 * other.normalized());
  return path;
}

struct PathResult {
  MaterialState state;
  long substeps = 0;
  long rejected = 0;
};

PathResult run_path(const Hypoplastic& model, bool with_igs) {
  PathResult run;
  run.state = start_state();
  if (with_igs) Hypoplastic::intergranular_strain(run.state) = -1e-4 * identity6() / kSqrt3;
  for (const Vec6& increment : strain_path()) {
    const UpdateResult result = model.update(run.state, increment);
    EXPECT_TRUE(result.ok) << result.message;
    run.substeps += result.substeps;
    run.rejected += result.rejected_substeps;
  }
  return run;
}

TEST(HypoplasticIntegrator, ErrorControlledResultConvergesAsTheToleranceShrinks) {
  const std::vector<double> tolerances = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
  for (const char* igs : {"none", "IGS3"}) {
    for (Scheme scheme : {Scheme::heun_euler, Scheme::bogacki_shampine}) {
      SCOPED_TRACE(std::string(igs) + " " + std::string(to_string(scheme)));
      const bool with_igs = std::string(igs) != "none";
      const PathResult reference =
          run_path(make_model(Scheme::bogacki_shampine, 1e-10, 0, igs), with_igs);
      std::vector<double> errors;
      std::vector<long> substeps;
      for (double tolerance : tolerances) {
        const PathResult run = run_path(make_model(scheme, tolerance, 0, igs), with_igs);
        errors.push_back(relative_difference(run.state.stress, reference.state.stress));
        substeps.push_back(run.substeps);
      }
      std::printf("[ measured ] tolerance sweep %s %s (reference: %ld sub-steps):", igs,
                  std::string(to_string(scheme)).c_str(), reference.substeps);
      for (std::size_t i = 0; i < tolerances.size(); ++i)
        std::printf(" tol %.0e: err %.2e (%ld)", tolerances[i], errors[i], substeps[i]);
      const double slope = std::log10(errors.front() / errors.back()) /
                           std::log10(tolerances.front() / tolerances.back());
      std::printf(", slope %.3f\n", slope);
      for (std::size_t i = 1; i < errors.size(); ++i) {
        EXPECT_LT(errors[i], errors[i - 1]) << "tolerance " << tolerances[i];
        EXPECT_GE(substeps[i], substeps[i - 1]);
      }
      if (!with_igs) {
        // Roughly proportional: the error falls by about a decade per decade of tolerance.
        EXPECT_NEAR(slope, 1.0, 0.3);
      } else {
        // With the intergranular strain the rate switches branch (sign of delta_hat:D) and
        // ||delta|| <= R is restored by projection inside an increment, so the right-hand side is
        // only piecewise smooth and the decrease is less regular: at least 2.4 decades over 4.
        EXPECT_GT(slope, 0.6);
      }
      // The global error stays within a decade of the local tolerance.
      EXPECT_LT(errors.back(), 10.0 * tolerances.back());
    }
  }
}

}  // namespace
}  // namespace pilempm
