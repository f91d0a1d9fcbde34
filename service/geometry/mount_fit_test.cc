// Fitting the mount's level from poses of a robot standing on a floor taken as level: the fit
// must find a mount error it was not told, say honestly how well it knows it, measure how
// level the floor was, and leave out a pose that does not belong.
#include "service/geometry/mount_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <iostream>
#include <random>

#include "service/geometry/robot_test_scenes.h"

namespace monocle {
namespace {

using Matrix5d = Eigen::Matrix<double, 5, 5>;
using Vector5d = Eigen::Matrix<double, 5, 1>;
constexpr double kDeg = M_PI / 180;

// The mount as configured when the true one is `truth` turned back by `error_rad` about the
// base's x and then y axis: FitMountLevel's correction should then be `error_rad`.
RigidTransform WrongMount(const RigidTransform& truth, const Eigen::Vector2d& error_rad) {
  RigidTransform wrong = truth;
  wrong.rotation = Eigen::AngleAxisd(-error_rad.y(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(-error_rad.x(), Eigen::Vector3d::UnitX()) * truth.rotation;
  return wrong;
}

struct Drive {
  std::vector<MountFitPose> poses;
};

// `count` poses of a camera on `mount`, the robot at headings spread over `heading_span_rad`,
// its floor tipped by N(0, floor_sigma_rad) about each horizontal axis, each pose solved with
// errors drawn from its own covariance (angles 0.03-0.3 degrees 1 sigma, as the realistic
// renders' views range).
Drive DriveOn(const RigidTransform& mount, int count, double floor_sigma_rad,
              double heading_span_rad, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> heading(0, heading_span_rad), sigma_deg(0.03, 0.3),
      place(1.0, 5.0), correlation(-0.5, 0.5);
  std::normal_distribution<double> normal;
  Drive d;
  for (int i = 0; i < count; ++i) {
    const Eigen::Matrix3d corner_from_base = testing::CornerFromBase(
        heading(rng), floor_sigma_rad * normal(rng), floor_sigma_rad * normal(rng));
    const CornerPose truth =
        testing::TruePose(corner_from_base, mount, Eigen::Vector3d(place(rng), place(rng), 1.8));
    Matrix5d l = Matrix5d::Zero();
    l(0, 0) = l(1, 1) = 0.004;
    for (int k = 2; k < 5; ++k) l(k, k) = sigma_deg(rng) * kDeg;
    l(4, 2) = correlation(rng) * l(2, 2);  // pan and swing move together in steep views
    l(0, 3) = 2 * l(3, 3);                 // x follows the tilt
    Vector5d draw;
    for (int k = 0; k < 5; ++k) draw[k] = normal(rng);
    d.poses.push_back({MovedBy(truth, l * draw), l * l.transpose()});
  }
  return d;
}

TEST(MountFitTest, FindsAMountErrorItWasNotToldAndSaysHowWellItKnowsIt) {
  const RigidTransform truth = testing::MountLookingUp(50, 2);
  const Eigen::Vector2d error(0.8 * kDeg, -0.5 * kDeg);
  std::mt19937_64 rng(7);
  double z2_sum = 0, floor_sum = 0;
  constexpr int kTrials = 200;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Drive d = DriveOn(truth, 40, 0.1 * kDeg, 2 * M_PI, rng);
    const auto fit = FitMountLevel(d.poses, WrongMount(truth, error));
    ASSERT_TRUE(fit.ok()) << fit.error();
    const Eigen::Vector2d off = fit->correction_rad - error;
    z2_sum += off.dot(fit->covariance.ldlt().solve(off));
    floor_sum += fit->floor_sigma_rad;
    if (trial == 0) {
      // The fitted mount puts the base's up axis where the true one does.
      const Eigen::Vector3d up_fit = fit->mount.rotation.inverse() * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d up_true = truth.rotation.inverse() * Eigen::Vector3d::UnitZ();
      EXPECT_LT(std::acos(std::min(1.0, up_fit.dot(up_true))), 0.1 * kDeg);
      EXPECT_LT(std::sqrt(fit->covariance.trace()), 0.05 * kDeg) << "40 poses pin it down";
      EXPECT_EQ(fit->used.size(), 40u);
    }
  }
  std::cout << "mean (error / 1 sigma)^2 " << z2_sum / kTrials << " (2 if honest), floor "
            << floor_sum / kTrials / kDeg << " deg (0.1)\n";
  // (error / 1 sigma)^2 of two coordinates averages 2 when the covariance is honest; the mean
  // over 200 trials scatters by 0.14.
  EXPECT_GT(z2_sum / kTrials, 1.6);
  EXPECT_LT(z2_sum / kTrials, 2.5);
  // The floor's 1 sigma, 0.1 degrees, measured from what the poses' own 1 sigma leave over.
  EXPECT_NEAR(floor_sum / kTrials, 0.1 * kDeg, 0.02 * kDeg);
}

TEST(MountFitTest, ALevelFloorMeasuresAsLevel) {
  const RigidTransform truth = testing::MountLookingUp(35, -4);
  std::mt19937_64 rng(8);
  const Drive d = DriveOn(truth, 60, 0, 2 * M_PI, rng);
  const auto fit = FitMountLevel(d.poses, truth);
  ASSERT_TRUE(fit.ok()) << fit.error();
  EXPECT_LT(fit->floor_sigma_rad, 0.03 * kDeg);
  EXPECT_LT(fit->correction_rad.norm(), 3 * std::sqrt(fit->covariance.trace()));
}

// A floor corner read as the ceiling's (or a pose on a ramp) tips the base by degrees: it is
// left out and named, and the fit rests on the others.
TEST(MountFitTest, APoseThatTipsTheBaseByDegreesIsLeftOut) {
  const RigidTransform truth = testing::MountLookingUp(50, 0);
  const Eigen::Vector2d error(-0.4 * kDeg, 0.6 * kDeg);
  std::mt19937_64 rng(9);
  Drive d = DriveOn(truth, 30, 0.05 * kDeg, 2 * M_PI, rng);
  d.poses[12].pose = testing::TruePose(testing::CornerFromBase(1.0, 4 * kDeg, 0), truth);
  const auto fit = FitMountLevel(d.poses, WrongMount(truth, error));
  ASSERT_TRUE(fit.ok()) << fit.error();
  ASSERT_EQ(fit->left_out.size(), 1u);
  EXPECT_EQ(fit->left_out[0], 12u);
  EXPECT_GT(fit->left_out_sigmas[0], 5);  // against the fit with it, whose floor it widened
  EXPECT_EQ(fit->used.size(), 29u);
  EXPECT_LT((fit->correction_rad - error).norm(), 0.05 * kDeg);
}

TEST(MountFitTest, SaysWhenThereAreTooFewPoses) {
  const RigidTransform truth = testing::MountLookingUp(50, 0);
  std::mt19937_64 rng(10);
  const Drive few = DriveOn(truth, 4, 0, 2 * M_PI, rng);
  const auto none = FitMountLevel(few.poses, truth);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("at least 5 corner poses (got 4)"), std::string::npos)
      << none.error().message;
}

}  // namespace
}  // namespace monocle
