#pragma once
// Symmetric second-order tensors in Mandel notation.
//
// A symmetric 3x3 tensor A is stored as the 6-vector
//   (A11, A22, A33, sqrt2*A23, sqrt2*A13, sqrt2*A12).
// With this scaling the double contraction A:B is the plain dot product, the Frobenius norm is the
// plain vector norm, and fourth-order tensors with minor symmetries are plain 6x6 matrices whose
// products and inverses are the tensor ones. Strains are stored the same way (tensor shear strain,
// not engineering shear strain).
#include <Eigen/Dense>
#include <array>
#include <cmath>

namespace pilempm {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

inline constexpr double kSqrt2 = 1.41421356237309504880;
inline constexpr double kSqrt3 = 1.73205080756887729353;
inline constexpr double kSqrt6 = 2.44948974278317809820;
inline constexpr double kPi = 3.14159265358979323846;

/// Index of each Mandel component; the off-diagonal ones carry the sqrt(2) factor.
enum MandelIndex : int { k11 = 0, k22 = 1, k33 = 2, k23 = 3, k13 = 4, k12 = 5 };

/// The second-order identity in Mandel notation.
inline Vec6 identity6() {
  Vec6 v;
  v << 1.0, 1.0, 1.0, 0.0, 0.0, 0.0;
  return v;
}

/// tr A.
inline double trace(const Vec6& a) {
  return a[0] + a[1] + a[2];
}

/// The deviatoric part A - (tr A / 3) I.
inline Vec6 deviator(const Vec6& a) {
  Vec6 d = a;
  const double m = trace(a) / 3.0;
  d[0] -= m;
  d[1] -= m;
  d[2] -= m;
  return d;
}

/// det A, from the Mandel components.
inline double determinant(const Vec6& a) {
  const double a23 = a[3] / kSqrt2, a13 = a[4] / kSqrt2, a12 = a[5] / kSqrt2;
  return a[0] * (a[1] * a[2] - a23 * a23) - a12 * (a12 * a[2] - a23 * a13) +
         a13 * (a12 * a23 - a[1] * a13);
}

/// A diagonal tensor from its three diagonal components.
inline Vec6 diagonal6(double a11, double a22, double a33) {
  Vec6 v;
  v << a11, a22, a33, 0.0, 0.0, 0.0;
  return v;
}

/// Mandel 6-vector to the full symmetric 3x3 matrix.
inline Mat3 to_matrix(const Vec6& a) {
  Mat3 m;
  const double a23 = a[3] / kSqrt2, a13 = a[4] / kSqrt2, a12 = a[5] / kSqrt2;
  m << a[0], a12, a13, a12, a[1], a23, a13, a23, a[2];
  return m;
}

/// Symmetric part of a 3x3 matrix to its Mandel 6-vector.
inline Vec6 from_matrix(const Mat3& m) {
  Vec6 a;
  a << m(0, 0), m(1, 1), m(2, 2), kSqrt2 * 0.5 * (m(1, 2) + m(2, 1)),
      kSqrt2 * 0.5 * (m(0, 2) + m(2, 0)), kSqrt2 * 0.5 * (m(0, 1) + m(1, 0));
  return a;
}

/// Ascending eigenvalues of a symmetric tensor.
inline Vec3 principal_values(const Vec6& a) {
  Eigen::SelfAdjointEigenSolver<Mat3> solver(to_matrix(a), Eigen::EigenvaluesOnly);
  return solver.eigenvalues();
}

/// The outer product A (x) B as a fourth-order tensor in Mandel notation.
inline Mat6 outer(const Vec6& a, const Vec6& b) {
  return a * b.transpose();
}

/// R A R^T for a rotation R, on the Mandel vector.
inline Vec6 rotate(const Vec6& a, const Mat3& rotation) {
  return from_matrix(rotation * to_matrix(a) * rotation.transpose());
}

}  // namespace pilempm
