// A camera mount looking ahead and up, and where such a mount puts the robot's base: written
// here from the geometry, not with monocle's code, for tests of --mount and of a camera's mount.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "idl/cli_output.pb.h"
#include "service/geometry/robot_test_scenes.h"

namespace monocle::testing {

// The optical frame in the base frame (x ahead, z up) of a camera looking ahead and up,
// `up_deg` from the vertical, upright: image right is the robot's right.
inline Eigen::Quaterniond CameraLookingUp(double up_deg) {
  return MountLookingUp(up_deg, 0).rotation;
}

// With the mount of CameraLookingUp at translation_m [0.1, 0, 0.4], the robot's base in the corner
// frame (Z down) lies 0.4 m below the optical centre and 0.1 m behind it along the optical axis's
// horizontal direction, which is also the base's heading; the camera stands at `truth` (x, y).
// Worked out here from the pose's own orientation, not with monocle's code.
inline void ExpectBaseUnderTheCamera(const proto::CornerOutput& pose,
                                     const std::array<double, 2>& truth) {
  ASSERT_TRUE(pose.has_base()) << "a camera with a mount: the base comes with every pose";
  const auto& q = pose.quaternion();  // w, x, y, z: optical frame -> corner frame
  ASSERT_EQ(q.size(), 4);
  const Eigen::Vector3d axis =
      Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector2d ahead = axis.head<2>().normalized();
  const auto& base = pose.base();
  EXPECT_NEAR(base.x(), pose.x() - 0.1 * ahead.x(), 2e-3);
  EXPECT_NEAR(base.y(), pose.y() - 0.1 * ahead.y(), 2e-3);
  EXPECT_NEAR(base.z(), pose.z() + 0.4, 2e-3);
  EXPECT_NEAR(
      std::remainder(base.heading_deg() - std::atan2(ahead.y(), ahead.x()) * 180 / M_PI, 360.0), 0,
      0.2);
  EXPECT_LT(
      std::hypot(base.x() - (truth[0] - 0.1 * ahead.x()), base.y() - (truth[1] - 0.1 * ahead.y())) /
          std::hypot(truth[0], truth[1]),
      0.01);
  // Its 1 sigma: of the pose's size, no less than the camera's own along each axis less the
  // heading's lever arm, and a full symmetric covariance.
  EXPECT_GT(base.sigma().x(), 0);
  EXPECT_LT(base.sigma().x(), 0.05);
  EXPECT_GT(base.sigma().heading_deg(), 0);
  EXPECT_LT(base.sigma().heading_deg(), 2);
  ASSERT_EQ(base.covariance_size(), 9);
  EXPECT_EQ(base.covariance(1), base.covariance(3));
  EXPECT_NEAR(std::sqrt(base.covariance(8)) * 180 / M_PI, base.sigma().heading_deg(), 1e-9);
}

}  // namespace monocle::testing
