#include "camera/render/driving_path.h"

#include <gtest/gtest.h>

#include <cmath>

namespace monocle {
namespace {

TEST(DrivingPathTest, SpeedIsConstantAndTheCornerStaysNearTheOpticalAxis) {
  DrivingPath path;
  path.speed_mps = 0.8;
  path.turn_deg_per_s = 0;
  const double dt = 1e-3;
  for (double t = 0; t < 5; t += 0.37) {
    const CornerPose a = DrivingPoseAt(path, t), b = DrivingPoseAt(path, t + dt);
    EXPECT_NEAR(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) / dt, 0.8, 1e-3);
    // Without sway the corner is on the optical axis up to the pitch and roll (1 degree).
    const Eigen::Vector3d c = CornerToCamera(a, Eigen::Vector3d::Zero());
    ASSERT_GT(c.z(), 0);
    EXPECT_LT(c.head<2>().norm() / c.z(), std::tan(1.2 * M_PI / 180)) << a;
    EXPECT_NEAR(a.z_m, path.ceiling_distance_m, 1e-12);
  }
}

TEST(DrivingPathTest, TheTurnRateIsWhatWasAsked) {
  DrivingPath path;
  path.speed_mps = 1e-6;  // nearly standing: the pan changes by the sway only
  path.turn_deg_per_s = 30;
  const double peak = PeakPanRateRadPerS(path, 0, path.sway_period_s, 1e-3);
  EXPECT_NEAR(peak * 180 / M_PI, 30, 0.1);
}

TEST(DrivingPathTest, ThePathIsContinuousAndEndless) {
  DrivingPath path;
  path.speed_mps = 1.0;
  path.turn_deg_per_s = 45;
  for (double t = 0; t < 60; t += 1.0 / 30) {
    const CornerPose a = DrivingPoseAt(path, t), b = DrivingPoseAt(path, t + 1.0 / 30);
    EXPECT_LT(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m), 1.0 / 30 + 1e-6);
    EXPECT_LT(std::abs(b.pan_rad - a.pan_rad), 0.05);  // no jump at a +-pi seam either
  }
}

TEST(DrivingPathTest, AClosedPathComesBackAsItWasAfterALap) {
  const DrivingPath path = ClosedDrivingPath(0.6, 25, 16.0 / 30);
  for (double t : {0.0, 0.1, 0.37}) {
    const CornerPose a = DrivingPoseAt(path, t), b = DrivingPoseAt(path, t + 16.0 / 30);
    EXPECT_NEAR(a.x_m, b.x_m, 1e-9);
    EXPECT_NEAR(a.y_m, b.y_m, 1e-9);
    EXPECT_NEAR(a.pan_rad, b.pan_rad, 1e-9);
    EXPECT_NEAR(a.tilt_rad, b.tilt_rad, 1e-9);
    EXPECT_NEAR(a.swing_rad, b.swing_rad, 1e-9);
  }
  const CornerPose a = DrivingPoseAt(path, 0), b = DrivingPoseAt(path, 1.0 / 30);
  EXPECT_NEAR(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m), 0.6 / 30, 1e-3);
  // A long lap sways several times rather than once, far: the corner stays within 15 degrees
  // of the optical axis at 45 deg/s.
  const DrivingPath long_lap = ClosedDrivingPath(1.0, 45, 10.0);
  EXPECT_NEAR(DrivingPoseAt(long_lap, 0).pan_rad, DrivingPoseAt(long_lap, 10.0).pan_rad, 1e-9);
  for (double t = 0; t < 10; t += 0.05) {
    const CornerPose p = DrivingPoseAt(long_lap, t);
    const Eigen::Vector3d c = CornerToCamera(p, Eigen::Vector3d::Zero());
    EXPECT_LT(std::atan2(c.head<2>().norm(), c.z()), 15 * M_PI / 180) << "at " << t << " s";
  }
}

}  // namespace
}  // namespace monocle
