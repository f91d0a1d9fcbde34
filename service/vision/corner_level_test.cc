// A located pose combined with its robot's level: made precise where the level allows, left
// alone and flagged where the level contradicts it.
#include "service/vision/corner_level.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

namespace monocle {
namespace {

constexpr double kDeg = M_PI / 180;

// The mount of a camera at `pose` on a base standing level, heading where the camera looks,
// tipped forward by `tip_rad` (the mount is that far off the camera's true tilt).
RigidTransform MountOf(const CornerPose& pose, double tip_rad) {
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(pose).transpose();
  const Eigen::Vector3d axis = corner_from_camera.col(2);
  Eigen::Matrix3d base;
  base.col(0) = Eigen::Vector3d(axis.x(), axis.y(), 0).normalized();
  base.col(2) = -Eigen::Vector3d::UnitZ();
  base.col(1) = base.col(2).cross(base.col(0));
  base = Eigen::AngleAxisd(tip_rad, base.col(1)).toRotationMatrix() * base;
  return {Eigen::Quaterniond(base.transpose() * corner_from_camera), Eigen::Vector3d::Zero()};
}

// A weakly determined view: its tilt known to 1 degree, x following it at 4 m per radian
// (horizontal 1 sigma 2.5 % of the distance), flagged for that alone.
CornerLocation WeakView() {
  CornerLocation c;
  c.pose = {2.5, 1.2, 1.6, 2.3, 50 * kDeg, 0.02};
  Eigen::Matrix<double, 5, 1> along;
  along << 4, 0, 0, 1, 0;
  c.covariance = along * along.transpose() * std::pow(1 * kDeg, 2);
  c.covariance.diagonal() += Eigen::Matrix<double, 5, 1>(1e-6, 1e-6, 1e-6, 1e-8, 1e-6);
  c.q_corner_camera = Eigen::Quaterniond(RotationCameraFromCorner(c.pose).transpose());
  c.suspect = c.suspect_only_imprecise = true;
  c.suspect_reason = "position uncertain: 1 sigma 2.5 % of the distance (more than 1.5)";
  return c;
}

TEST(CornerLevelTest, ALevelThatMakesAWeakViewPreciseLiftsItsFlag) {
  CornerLocation c = WeakView();
  MountLevelOptions level;
  level.level_sigma_rad = 0.1 * kDeg;
  ApplyMountLevel(MountOf(c.pose, 0), level, {}, &c);
  ASSERT_TRUE(c.level_error_rad.has_value());
  EXPECT_NEAR(*c.level_error_rad, 0, 1e-6);
  EXPECT_DOUBLE_EQ(c.level_sigma_rad, 0.1 * kDeg);
  EXPECT_LT(std::sqrt(c.covariance(3, 3)), 0.11 * kDeg);
  EXPECT_LT(std::sqrt(c.covariance(0, 0)), 0.2 * 4 * kDeg) << "x follows the tilt's 1 sigma";
  EXPECT_FALSE(c.suspect) << c.suspect_reason;
  EXPECT_TRUE(c.suspect_reason.empty());
  EXPECT_LT(c.q_corner_camera.angularDistance(
                Eigen::Quaterniond(RotationCameraFromCorner(c.pose).transpose())),
            1e-9);
}

TEST(CornerLevelTest, ALevelThatLeavesAViewImpreciseSaysSoWithItsNewSigma) {
  CornerLocation c = WeakView();
  MountLevelOptions level;
  level.level_sigma_rad = 1.0 * kDeg;  // no better than the view's own tilt
  ApplyMountLevel(MountOf(c.pose, 0), level, {}, &c);
  EXPECT_TRUE(c.suspect);
  EXPECT_TRUE(c.suspect_only_imprecise);
  EXPECT_NE(c.suspect_reason.find("with the mount's level"), std::string::npos) << c.suspect_reason;
}

// A view flagged for an edge as well as for its 1 sigma: the level changes the 1 sigma, so
// the imprecision is stated again with the new figure, or dropped; the edge's reason stands.
TEST(CornerLevelTest, AnotherReasonStandsAndTheImprecisionIsRestated) {
  const std::string edge_reason = "edge Y found on 23 % of its visible length";
  for (const double level_deg : {0.1, 1.0}) {
    CornerLocation c = WeakView();
    c.suspect_only_imprecise = false;
    c.suspect_reason = edge_reason + "; " + c.suspect_reason;
    MountLevelOptions level;
    level.level_sigma_rad = level_deg * kDeg;
    ApplyMountLevel(MountOf(c.pose, 0), level, {}, &c);
    EXPECT_TRUE(c.suspect);
    EXPECT_FALSE(c.suspect_only_imprecise);
    const double sigma_pct = 100 * std::sqrt(c.covariance(0, 0) + c.covariance(1, 1)) /
                             std::hypot(c.pose.x_m, c.pose.y_m);
    if (level_deg == 0.1) {
      EXPECT_LT(sigma_pct, 1.25);
      EXPECT_EQ(c.suspect_reason, edge_reason);
    } else {
      // The view's 1 degree of tilt combined with a level of 1 degree: over 1.25 %, under 2.5.
      char restated[128];
      std::snprintf(restated, sizeof restated,
                    "; position uncertain: 1 sigma %.1f %% of the distance with the mount's level "
                    "(more than 1.25)",
                    sigma_pct);
      EXPECT_GT(sigma_pct, 1.25);
      EXPECT_LT(sigma_pct, 2.4);
      EXPECT_EQ(c.suspect_reason, edge_reason + restated);
    }
  }
}

// 6 degrees off is 5.8 sigma of the view's own tilt (1 degree) and the level's (0.3).
TEST(CornerLevelTest, APoseTheLevelContradictsIsLeftAsSolvedAndFlagged) {
  CornerLocation c = WeakView();
  const CornerLocation before = c;
  ApplyMountLevel(MountOf(c.pose, 6 * kDeg), {}, {}, &c);
  ASSERT_TRUE(c.level_error_rad.has_value());
  EXPECT_NEAR(*c.level_error_rad, 6 * kDeg, 1e-6);
  EXPECT_EQ(c.pose.x_m, before.pose.x_m);
  EXPECT_EQ(c.pose.tilt_rad, before.pose.tilt_rad);
  EXPECT_EQ(c.covariance, before.covariance);
  EXPECT_TRUE(c.suspect);
  EXPECT_FALSE(c.suspect_only_imprecise) << "the edges or the mount are wrong, not just weak";
  EXPECT_NE(
      c.suspect_reason.find("the pose tips the robot 6.00 deg from level (allowed 1.00 deg; 5.8 "
                            "sigma of the pose's own and the level's)"),
      std::string::npos)
      << c.suspect_reason;
}

// A weakly determined view's own tilt may be a degree off: a mount 1.5 degrees from it is
// within its 1 sigma (1 degree) and the level's, so the two are combined, not refused.
TEST(CornerLevelTest, ATipWithinTheViewsOwnSigmaIsCombinedNotRefused) {
  CornerLocation c = WeakView();
  const double solved_tilt = c.pose.tilt_rad;
  MountLevelOptions level;
  level.level_sigma_rad = 0.1 * kDeg;
  ApplyMountLevel(MountOf(c.pose, 1.5 * kDeg), level, {}, &c);
  ASSERT_TRUE(c.level_error_rad.has_value());
  EXPECT_NEAR(*c.level_error_rad, 1.5 * kDeg, 1e-6);
  EXPECT_FALSE(c.suspect) << c.suspect_reason;
  // The tilt goes (almost) where the mount says: 1/(1 + 0.1^2) of the way.
  EXPECT_NEAR(std::abs(c.pose.tilt_rad - solved_tilt), 1.5 * kDeg / 1.01, 0.02 * kDeg);
}

}  // namespace
}  // namespace monocle
