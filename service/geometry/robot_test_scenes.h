// Cameras on robot bases for geometry tests: a mount written from the geometry (not from the
// corner solver's code), a base standing level or tipped, and the corner pose that results.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "service/geometry/corner_pose.h"
#include "service/geometry/robot_frames.h"

namespace monocle::testing {

// A camera looking ahead and up, `up_deg` from the vertical, rolled `roll_deg` about its
// axis, on a base whose z is up.
inline RigidTransform MountLookingUp(double up_deg, double roll_deg) {
  constexpr double kDeg = std::numbers::pi / 180;
  const double t = up_deg * kDeg;
  const Eigen::Vector3d z(std::sin(t), 0, std::cos(t));  // optical axis in the base frame
  const Eigen::Vector3d x(0, -1, 0);                     // image right = the robot's right
  Eigen::Matrix3d r;
  r << x, z.cross(x), z;
  r = r * Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return {Eigen::Quaterniond(r), Eigen::Vector3d(0.1, 0, 0.4)};
}

// The base in the corner frame (Z down the wall edge): heading `heading_rad` from X, tipped
// by `tip_x_rad`, `tip_y_rad` about the corner frame's X and Y axes.
inline Eigen::Matrix3d CornerFromBase(double heading_rad, double tip_x_rad = 0,
                                      double tip_y_rad = 0) {
  Eigen::Matrix3d level;
  level.col(0) = Eigen::Vector3d(std::cos(heading_rad), std::sin(heading_rad), 0);
  level.col(2) = -Eigen::Vector3d::UnitZ();
  level.col(1) = level.col(2).cross(level.col(0));
  return (Eigen::AngleAxisd(tip_x_rad, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(tip_y_rad, Eigen::Vector3d::UnitY()))
             .toRotationMatrix() *
         level;
}

// The camera's corner pose on that base and mount, the camera at `position_m`.
inline CornerPose TruePose(const Eigen::Matrix3d& corner_from_base, const RigidTransform& mount,
                           const Eigen::Vector3d& position_m = Eigen::Vector3d(1.8, 2.6, 2.0)) {
  const Eigen::Matrix3d corner_from_camera = corner_from_base * mount.rotation.toRotationMatrix();
  return PoseFromRotation(corner_from_camera.transpose(), position_m);
}

}  // namespace monocle::testing
