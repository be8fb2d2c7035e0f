// Mandel notation: the 6-vector operations must equal the 3x3 tensor operations they stand for.
#include <gtest/gtest.h>

#include <random>

#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"

namespace pilempm {
namespace {

Mat3 random_symmetric(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = u(rng);
  return 0.5 * (m + m.transpose());
}

Mat3 random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  return q.normalized().toRotationMatrix();
}

TEST(Tensor, MandelRoundTripAndDoubleContraction) {
  std::mt19937 rng(7);
  for (int k = 0; k < 100; ++k) {
    const Mat3 a = random_symmetric(rng), b = random_symmetric(rng);
    const Vec6 va = from_matrix(a), vb = from_matrix(b);
    EXPECT_LT((to_matrix(va) - a).norm(), 1e-15);
    // A:B = tr(A B^T) is the plain dot product of the Mandel vectors.
    EXPECT_NEAR(va.dot(vb), (a * b.transpose()).trace(), 1e-14);
    EXPECT_NEAR(va.norm(), a.norm(), 1e-14);
    EXPECT_NEAR(trace(va), a.trace(), 1e-15);
    EXPECT_NEAR(determinant(va), a.determinant(), 1e-14);
  }
}

TEST(Tensor, DeviatorIsTracelessAndOrthogonalToIdentity) {
  std::mt19937 rng(3);
  const Vec6 a = from_matrix(random_symmetric(rng));
  const Vec6 d = deviator(a);
  EXPECT_NEAR(trace(d), 0.0, 1e-15);
  EXPECT_NEAR(d.dot(identity6()), 0.0, 1e-15);
  EXPECT_LT((a - d - trace(a) / 3.0 * identity6()).norm(), 1e-15);
}

TEST(Tensor, RotationKeepsPrincipalValues) {
  std::mt19937 rng(11);
  for (int k = 0; k < 20; ++k) {
    const Vec6 a = from_matrix(random_symmetric(rng));
    const Mat3 r = random_rotation(rng);
    const Vec6 b = rotate(a, r);
    EXPECT_LT((principal_values(a) - principal_values(b)).norm(), 1e-13);
    EXPECT_NEAR(a.norm(), b.norm(), 1e-14);
  }
}

TEST(Tensor, OuterProductActsAsFourthOrderTensor) {
  std::mt19937 rng(5);
  const Vec6 a = from_matrix(random_symmetric(rng)), b = from_matrix(random_symmetric(rng));
  const Vec6 x = from_matrix(random_symmetric(rng));
  // (A (x) B) : X = A (B : X)
  EXPECT_LT((outer(a, b) * x - a * b.dot(x)).norm(), 1e-14);
}

TEST(Errors, InputErrorNamesFileLineKeyAndValue) {
  const InputError e("case.toml", 12, "sigma3_kPa", "-5", "must be > 0");
  EXPECT_STREQ(e.what(), "case.toml:12: sigma3_kPa = -5: must be > 0");
  const InvalidValue v("n", "1.5", "in (0, 1)");
  EXPECT_STREQ(v.what(), "n = 1.5 is not allowed: must be in (0, 1)");
}

}  // namespace
}  // namespace pilempm
