// Random strain paths through hypoplasticity with the intergranular strain: whatever the
// increments, every update must succeed and leave an admissible state (finite, no tensile
// principal stress, p >= p_min, e inside [e_d(p), e_i(p)], ||delta|| <= R).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"

namespace pilempm {
namespace {

struct FuzzStart {
  const char* label;
  double p;                 // isotropic initial mean stress [Pa]
  double density_position;  // e = e_d + position (e_i - e_d) at p
};

struct FuzzReport {
  long increments = 0;
  long failures = 0;  // increments that broke an invariant
  long floor_hits = 0;
  long resets = 0;
  long substeps = 0;
  long rejected = 0;
  int max_substeps = 0;
  double max_void_ratio_excess = 0.0;
  double max_void_ratio_excess_off_floor = 0.0;  // in updates without a floor hit
  double max_p = 0.0;
  double min_p = 1e300;
  std::string first_failure;
};

std::string describe(const MaterialState& before, const Vec6& increment, const MaterialState& after,
                     const UpdateResult& result, const char* what) {
  std::ostringstream out;
  out.precision(17);
  out << what << ": message '" << result.message << "'\n  stress before "
      << before.stress.transpose() << "\n  e before " << before.void_ratio << ", delta before "
      << Hypoplastic::intergranular_strain(before).transpose() << "\n  increment "
      << increment.transpose() << "\n  stress after " << after.stress.transpose() << "\n  e after "
      << after.void_ratio;
  return out.str();
}

// Runs `count` random increments from each start, resetting the point when its path has run far.
FuzzReport fuzz(const Hypoplastic& model, const std::vector<FuzzStart>& starts, long count,
                std::uint64_t seed) {
  const auto& par = model.parameters();
  const double R = model.intergranular().R;
  const double p_min = model.integrator().min_mean_stress;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  FuzzReport report;

  for (const auto& start : starts) {
    auto fresh = [&] {
      MaterialState state;
      state.stress = -start.p * identity6();
      const auto band = limit_void_ratios(par, start.p);
      state.void_ratio = band.e_d + start.density_position * (band.e_i - band.e_d);
      Hypoplastic::intergranular_strain(state) = -R / kSqrt3 * identity6();
      return state;
    };
    MaterialState state = fresh();
    double travelled = 0.0;
    for (long i = 0; i < count; ++i) {
      // Reset once the path has gone far (1 % to 10 % of accumulated strain, random).
      if (travelled > 0.01 + 0.09 * uniform(rng)) {
        state = fresh();
        travelled = 0.0;
        ++report.resets;
      }
      // Log-uniform size in [1e-7, 1e-3]; direction uniform on the 6-sphere, or biased towards
      // compression (half of the increments) so that paths do not only pull the sample apart.
      const double size = std::pow(10.0, -7.0 + 4.0 * uniform(rng));
      Vec6 direction;
      for (int k = 0; k < 6; ++k) direction[k] = normal(rng);
      direction.normalize();
      if (uniform(rng) < 0.5) direction = (direction - 1.5 * identity6() / kSqrt3).normalized();
      const Vec6 increment = size * direction;
      travelled += size;

      const MaterialState before = state;
      const UpdateResult result = model.update(state, increment);
      ++report.increments;
      report.floor_hits += result.mean_stress_floor_hits;
      report.substeps += result.substeps;
      report.rejected += result.rejected_substeps;
      report.max_substeps =
          std::max(report.max_substeps, result.substeps + result.rejected_substeps);
      report.max_void_ratio_excess =
          std::max(report.max_void_ratio_excess, result.void_ratio_excess);

      const char* broken = nullptr;
      const double p = mean_stress(state.stress);
      if (!result.ok) {
        broken = "update failed";
      } else if (!state.stress.allFinite() || !std::isfinite(state.void_ratio) ||
                 !Hypoplastic::intergranular_strain(state).allFinite()) {
        broken = "non-finite state";
      } else if (p < p_min * (1.0 - 1e-12)) {
        broken = "mean stress below the floor";
      } else if (principal_values(state.stress).maxCoeff() > 1e-12 * state.stress.norm()) {
        broken = "tensile principal stress";
      } else {
        const auto band = limit_void_ratios(par, p);
        if (state.void_ratio < band.e_d * (1.0 - 1e-12) ||
            state.void_ratio > band.e_i * (1.0 + 1e-12))
          broken = "void ratio outside [e_d(p), e_i(p)]";
        else if (Hypoplastic::intergranular_strain(state).norm() > R * (1.0 + 1e-12))
          broken = "||delta|| > R";
      }
      if (broken != nullptr) {
        if (report.failures++ == 0)
          report.first_failure = std::string(start.label) + ", increment " + std::to_string(i) +
                                 ": " + describe(before, increment, state, result, broken);
        state = fresh();  // go on from a clean state to see how common the failure is
        travelled = 0.0;
        continue;
      }
      report.max_p = std::max(report.max_p, p);
      report.min_p = std::min(report.min_p, p);
    }
  }
  return report;
}

const std::vector<FuzzStart>& starts() {
  static const std::vector<FuzzStart> list = {
      {"1 kPa dense", 1e3, 0.1},   {"1 kPa loose", 1e3, 0.9},   {"100 kPa dense", 1e5, 0.1},
      {"100 kPa loose", 1e5, 0.9}, {"10 MPa dense", 1e7, 0.1},  {"10 MPa loose", 1e7, 0.9},
      {"1 kPa at e_i", 1e3, 1.0},  {"10 MPa at e_d", 1e7, 0.0},
  };
  return list;
}

void run_and_check(const char* igs, IntegratorSettings::Scheme scheme, long per_start,
                   std::uint64_t seed) {
  IntegratorSettings settings;
  settings.scheme = scheme;
  const Hypoplastic model(hypoplastic_set("original"), intergranular_strain_set(igs), settings);
  const auto begin = std::chrono::steady_clock::now();
  const FuzzReport report = fuzz(model, starts(), per_start, seed);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  std::printf(
      "[ measured ] fuzz %s %s: %ld increments in %.2f s, %ld failures, %ld resets, %ld floor "
      "hits, "
      "%.2f sub-steps/increment (max %d incl. rejected), %ld rejected, max void_ratio_excess "
      "%.2e (%.2e without floor hits), p in [%.3g, %.3g] Pa\n",
      igs, std::string(to_string(scheme)).c_str(), report.increments, seconds, report.failures,
      report.resets, report.floor_hits,
      static_cast<double>(report.substeps) / static_cast<double>(report.increments),
      report.max_substeps, report.rejected, report.max_void_ratio_excess,
      report.max_void_ratio_excess_off_floor, report.min_p, report.max_p);
  EXPECT_EQ(report.failures, 0) << report.first_failure;
  // The void ratio clamp acts only on sand that has separated (floor hits); elsewhere the
  // integration keeps e inside [e_d, e_i] on its own (measured: exactly 0).
  EXPECT_LE(report.max_void_ratio_excess_off_floor, 1e-6);
  EXPECT_EQ(report.increments, per_start * static_cast<long>(starts().size()));
  // The fuzz really visits the edges: the stress-free floor, and stresses far from the starts.
  EXPECT_GT(report.floor_hits, 0);
  EXPECT_GT(report.resets, 100);
  EXPECT_GT(report.max_p, 2e7);
}

TEST(HypoplasticFuzz, RandomIncrementsKeepTheStateAdmissible) {
  run_and_check("IGS3", IntegratorSettings::Scheme::heun_euler, 15000, 20240601);  // 1.2e5
  run_and_check("none", IntegratorSettings::Scheme::bogacki_shampine, 5000, 42);   // 3e4
}

TEST(HypoplasticFuzz, LongRandomIncrementsKeepTheStateAdmissible) {
  run_and_check("IGS3", IntegratorSettings::Scheme::heun_euler, 150000, 7);
  run_and_check("IGS3", IntegratorSettings::Scheme::bogacki_shampine, 150000, 8);
  run_and_check("IGS1", IntegratorSettings::Scheme::heun_euler, 75000, 9);
  run_and_check("none", IntegratorSettings::Scheme::heun_euler, 75000, 10);
}

}  // namespace
}  // namespace pilempm
