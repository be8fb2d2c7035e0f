// Isotropic linear elasticity against closed forms, and its parameter validation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "pilempm/constitutive/linear_elastic/linear_elastic.hpp"
#include "pilempm/core/error.hpp"

namespace pilempm {
namespace {

constexpr double kE = 30.0e6;
constexpr double kNu = 0.25;

// Uniaxial (oedometric) strain eps along x: s_xx = E(1-nu)/((1+nu)(1-2nu)) eps,
// s_yy = s_zz = E nu/((1+nu)(1-2nu)) eps.
TEST(LinearElastic, UniaxialStrainMatchesClosedForm) {
  const LinearElastic model({kE, kNu});
  MaterialState state;
  state.stress = diagonal6(-50e3, -20e3, -20e3);
  state.void_ratio = 0.8;
  const double eps = -2e-4;
  Vec6 d_eps = Vec6::Zero();
  d_eps[k11] = eps;
  const UpdateResult result = model.update(state, d_eps);
  ASSERT_TRUE(result.ok);
  const double factor = kE / ((1.0 + kNu) * (1.0 - 2.0 * kNu));
  EXPECT_NEAR(state.stress[k11], -50e3 + factor * (1.0 - kNu) * eps, 1e-6);
  EXPECT_NEAR(state.stress[k22], -20e3 + factor * kNu * eps, 1e-6);
  EXPECT_NEAR(state.stress[k33], -20e3 + factor * kNu * eps, 1e-6);
  for (int i = 3; i < 6; ++i) EXPECT_EQ(state.stress[i], 0.0);
  EXPECT_NEAR(state.void_ratio, 0.8 + 1.8 * eps, 1e-15);
}

// Simple shear: the tensor shear strain eps_12 gives s_12 = 2 G eps_12 (Mandel: the same factor).
TEST(LinearElastic, ShearMatchesClosedForm) {
  const LinearElastic model({kE, kNu});
  MaterialState state;
  const double gamma = 1e-4;  // engineering shear strain 2 eps_12
  Vec6 d_eps = Vec6::Zero();
  d_eps[k12] = kSqrt2 * gamma / 2.0;
  ASSERT_TRUE(model.update(state, d_eps).ok);
  const double g = kE / (2.0 * (1.0 + kNu));
  EXPECT_NEAR(to_matrix(state.stress)(0, 1), g * gamma, 1e-9);
  EXPECT_NEAR(trace(state.stress), 0.0, 1e-9);
}

TEST(LinearElastic, ModuliAndWaveModulus) {
  const ElasticParameters p{kE, kNu};
  EXPECT_NEAR(p.bulk_modulus(), kE / (3.0 * (1.0 - 2.0 * kNu)), 1e-6);
  EXPECT_NEAR(p.shear_modulus(), kE / (2.0 * (1.0 + kNu)), 1e-6);
  const LinearElastic model(p);
  const double constrained = kE * (1.0 - kNu) / ((1.0 + kNu) * (1.0 - 2.0 * kNu));
  EXPECT_NEAR(model.wave_modulus(MaterialState{}), constrained, 1e-9 * constrained);
  // The tangent maps an isotropic strain to 3K times it and a deviatoric one to 2G times it.
  const Mat6 d = model.tangent(MaterialState{}, Vec6::Zero());
  EXPECT_NEAR((d * identity6() - 3.0 * p.bulk_modulus() * identity6()).norm(), 0.0, 1e-6);
  const Vec6 dev = diagonal6(1.0, -0.5, -0.5);
  EXPECT_NEAR((d * dev - 2.0 * p.shear_modulus() * dev).norm(), 0.0, 1e-6);
}

TEST(LinearElastic, ValidationNamesTheKey) {
  auto key_of = [](const ElasticParameters& p) -> std::string {
    try {
      p.validate();
    } catch (const InvalidValue& e) {
      EXPECT_NE(std::string(e.what()).find(e.key()), std::string::npos);
      return e.key();
    }
    return "";
  };
  EXPECT_NE(key_of({0.0, 0.3}).find("young_modulus"), std::string::npos);
  EXPECT_NE(key_of({-1.0, 0.3}).find("young_modulus"), std::string::npos);
  EXPECT_NE(key_of({std::numeric_limits<double>::quiet_NaN(), 0.3}).find("young_modulus"),
            std::string::npos);
  EXPECT_NE(key_of({kE, 0.5}).find("poisson_ratio"), std::string::npos);
  EXPECT_NE(key_of({kE, -1.0}).find("poisson_ratio"), std::string::npos);
  EXPECT_EQ(key_of({kE, 0.0}), "");
  EXPECT_THROW(LinearElastic({kE, 0.6}), InvalidValue);
}

}  // namespace
}  // namespace pilempm
