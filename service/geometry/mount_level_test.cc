// The mount's level combined with a corner pose: it must move a pose to the truth as far as
// its covariance says, and its covariance must then still say how far the truth is (checked
// by sampling the pose's errors and the floor's tip).
#include "service/geometry/mount_level.h"
#include "service/geometry/robot_test_scenes.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace monocle {
namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Matrix5d = Eigen::Matrix<double, 5, 5>;
constexpr double kDeg = M_PI / 180;

using testing::CornerFromBase;
using testing::MountLookingUp;
using testing::TruePose;

Vector5d Difference(const CornerPose& a, const CornerPose& b) {
  auto wrap = [](double r) { return std::remainder(r, 2 * M_PI); };
  return (Vector5d() << a.x_m - b.x_m, a.y_m - b.y_m, wrap(a.pan_rad - b.pan_rad),
          wrap(a.tilt_rad - b.tilt_rad), wrap(a.swing_rad - b.swing_rad))
      .finished();
}

// A weakly determined view's covariance: the tilt 0.6 degrees, x following it (2 m per
// radian, correlation 0.9), swing and pan 0.4-0.6 degrees, y following the swing.
Matrix5d WeakViewCovariance() {
  Matrix5d l = Matrix5d::Zero();
  l(3, 3) = 0.6 * kDeg;
  l(0, 3) = 2 * 0.6 * kDeg;
  l(0, 0) = 0.005;
  l(4, 4) = 0.6 * kDeg;
  l(1, 4) = 1.2 * 0.6 * kDeg;
  l(1, 1) = 0.01;
  l(2, 2) = 0.4 * kDeg;
  l(4, 2) = 0.2 * kDeg;
  return l * l.transpose();
}

TEST(MountLevelTest, ALevelPoseIsLeftWhereItIs) {
  const RigidTransform mount = MountLookingUp(35, 3);
  const CornerPose truth = TruePose(CornerFromBase(0.7), mount);
  EXPECT_LT(BaseTipInCornerFrame(truth, mount).norm(), 1e-12);
  const LevelledCornerPose same = LevelWithMount(truth, WeakViewCovariance(), mount, 0.3 * kDeg);
  EXPECT_NEAR(same.level_error_rad, 0, 1e-7);
  EXPECT_LT(Difference(same.pose, truth).norm(), 1e-9);
  // The level is information: every variance shrinks or stays.
  for (int i = 0; i < 5; ++i) EXPECT_LE(same.covariance(i, i), WeakViewCovariance()(i, i) + 1e-15);
  EXPECT_LT(same.covariance(3, 3), 0.3 * WeakViewCovariance()(3, 3));
  EXPECT_LT(same.covariance(0, 0), 0.5 * WeakViewCovariance()(0, 0));
}

TEST(MountLevelTest, APoseTippedAlongItsCovarianceIsTakenBack) {
  const RigidTransform mount = MountLookingUp(60, 0);
  const CornerPose truth = TruePose(CornerFromBase(-1.2), mount);
  // The pose erred along the covariance's strongest direction: tilt 1 degree, x with it.
  const Vector5d along = (Vector5d() << 2, 0, 0, 1, 0).finished();
  const Matrix5d covariance = along * along.transpose() * 1e-4 + 1e-12 * Matrix5d::Identity();
  const CornerPose solved = MovedBy(truth, along * kDeg);
  const LevelledCornerPose fixed = LevelWithMount(solved, covariance, mount, 1e-6);
  EXPECT_NEAR(fixed.level_error_rad, 1 * kDeg, 1e-6);
  EXPECT_LT(Difference(fixed.pose, truth).cwiseAbs().maxCoeff(), 1e-6);
}

// The truth falls within the levelled covariance as often as a Gaussian says, for a steep
// camera (15 degrees from the vertical, where the base's roll moves pan and swing together and
// a prior on swing alone is overconfident), a middling one and a nearly level one.
void ExpectHonestCovariance(double up_deg) {
  const RigidTransform mount = MountLookingUp(up_deg, 4);
  const Matrix5d covariance = WeakViewCovariance();
  const Eigen::Matrix<double, 5, 5> l = covariance.llt().matrixL();
  const double level_sigma = 0.3 * kDeg;
  std::mt19937_64 rng(20261126);
  std::normal_distribution<double> normal;
  constexpr int kTrials = 4000;
  double z2_sum = 0;
  Vector5d ratio_sum = Vector5d::Zero();
  for (int trial = 0; trial < kTrials; ++trial) {
    const double heading = 2 * M_PI * trial / kTrials;
    const CornerPose truth = TruePose(
        CornerFromBase(heading, level_sigma * normal(rng), level_sigma * normal(rng)), mount);
    Vector5d noise;
    for (int i = 0; i < 5; ++i) noise[i] = normal(rng);
    const LevelledCornerPose levelled =
        LevelWithMount(MovedBy(truth, l * noise), covariance, mount, level_sigma);
    const Vector5d error = Difference(levelled.pose, truth);
    z2_sum += error.dot(levelled.covariance.ldlt().solve(error));
    ratio_sum += error.cwiseAbs2().cwiseQuotient(levelled.covariance.diagonal());
  }
  // Mean (error / sigma)^2 is 1 per coordinate, 5 in all (4000 trials: +-2 %).
  EXPECT_NEAR(z2_sum / kTrials / 5, 1.0, 0.08) << up_deg << " degrees from the vertical";
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(ratio_sum[i] / kTrials, 1.0, 0.1) << "coordinate " << i << " at " << up_deg;
}

TEST(MountLevelTest, TheLevelledCovarianceIsHonestForASteepCamera) { ExpectHonestCovariance(15); }
TEST(MountLevelTest, TheLevelledCovarianceIsHonestForAMiddlingCamera) {
  ExpectHonestCovariance(50);
}
TEST(MountLevelTest, TheLevelledCovarianceIsHonestForANearlyLevelCamera) {
  ExpectHonestCovariance(80);
}

}  // namespace
}  // namespace monocle
