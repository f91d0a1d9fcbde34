#include "service/geometry/pose_covariance.h"

#include <gtest/gtest.h>

#include <random>

namespace monocle {
namespace {

// Draw angle errors from the 5x5 covariance, turn each into the exact rotation vector, and
// compare the sample covariance with the first-order one.
TEST(PoseCovarianceTest, RotationPartMatchesSampledRotations) {
  const CornerPose pose{2.0, 1.5, 1.6, 2.2, 0.9, 0.1};
  Eigen::Matrix<double, 5, 5> c = Eigen::Matrix<double, 5, 5>::Zero();
  c.diagonal() << 1e-4, 4e-4, 1e-5, 4e-6, 9e-6;
  c(2, 4) = c(4, 2) = 0.5 * std::sqrt(1e-5 * 9e-6);  // pan and swing correlated
  c(0, 2) = c(2, 0) = 0.3 * std::sqrt(1e-4 * 1e-5);  // x and pan correlated
  const Eigen::Matrix<double, 6, 6> ros = RosPoseCovariance(pose, c);
  const Eigen::Matrix<double, 5, 5> l = c.llt().matrixL();
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0, 1);
  Eigen::Matrix<double, 6, 6> sampled = Eigen::Matrix<double, 6, 6>::Zero();
  constexpr int kSamples = 20000;
  for (int s = 0; s < kSamples; ++s) {
    Eigen::Matrix<double, 5, 1> z;
    for (int i = 0; i < 5; ++i) z[i] = n(rng);
    const Eigen::Matrix<double, 5, 1> d = l * z;
    Eigen::Matrix<double, 6, 1> v;
    v << d[0], d[1], 0, RotationChange(pose, d.tail<3>());
    sampled += v * v.transpose() / kSamples;
  }
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b < 6; ++b) {
      const double scale = std::sqrt(ros(a, a) * ros(b, b));
      EXPECT_NEAR(sampled(a, b), ros(a, b), 0.05 * scale + 1e-15) << a << "," << b;
    }
  }
  EXPECT_EQ(ros(2, 2), 0);  // the ceiling distance is given, not measured
  EXPECT_DOUBLE_EQ(ros(0, 0), c(0, 0));
  EXPECT_DOUBLE_EQ(ros(1, 1), c(1, 1));
  // A rotation covariance of angles is not the angles' own: the check would be pointless if
  // they happened to coincide.
  const Eigen::Matrix3d angles = c.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d rotation = ros.bottomRightCorner<3, 3>();
  EXPECT_GT((rotation - angles).norm(), 0.1 * angles.norm());
}

// ROS consumers read the 36 numbers as published: the matrix must be exactly symmetric,
// not only to rounding (J C J^T rounds its two triangles differently).
TEST(PoseCovarianceTest, IsExactlySymmetric) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const CornerPose pose{2.0 + u(rng), 1.5 + u(rng),       1.6,
                          2.2 + u(rng), 0.9 + 0.3 * u(rng), 0.2 * u(rng)};
    Eigen::Matrix<double, 5, 5> a;
    for (int i = 0; i < 25; ++i) a(i / 5, i % 5) = 1e-3 * u(rng);
    const Eigen::Matrix<double, 5, 5> c = a * a.transpose();  // a covariance, full rank
    const Eigen::Matrix<double, 6, 6> ros = RosPoseCovariance(pose, c);
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < r; ++k) ASSERT_EQ(ros(r, k), ros(k, r)) << trial << ": " << r << k;
  }
}

}  // namespace
}  // namespace monocle
