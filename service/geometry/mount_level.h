// The mount's level: a camera on a robot standing on a level floor has the tilt and swing its
// mount gives it, whatever the robot's heading. The corner solve measures them freely from
// the image; this combines the two. Pure geometry: Eigen only, no I/O.
//
// The measurement is the robot base's up axis, which on a level floor points straight up
// (along -Z of the corner frame, whose Z runs down the wall edge). Its two horizontal
// components are the base's tip about two horizontal axes, each zero with 1 sigma
// `level_sigma_rad` (the floor's slope, the robot's suspension, the mount's own error). How
// they depend on the camera's pan, tilt and swing is the rotation's own Jacobian: a base
// rolled about its forward axis moves a camera's swing and pan together, which a prior on
// (tilt, swing) alone counts as swing only (the room map's update until 2026-11-26: its
// covariance came out overconfident in swing, and for a steep camera in pan and y too, failing
// mount_level_test at 15 and 50 degrees from the vertical).
#pragma once

#include <Eigen/Core>

#include "service/geometry/corner_pose.h"
#include "service/geometry/robot_frames.h"

namespace monocle {

// The corner pose and covariance of (x, y, pan, tilt, swing) combined with the mount's level,
// and how far from level the pose as solved put the base.
struct LevelledCornerPose {
  CornerPose pose;
  Eigen::Matrix<double, 5, 5> covariance;
  double level_error_rad = 0;
  // The pose as solved's tip measured against what its own covariance and the level allow:
  // tip^T (H P H^T + level^2 I)^-1 tip, chi-square with 2 degrees of freedom if the two agree.
  double tip_mahalanobis2 = 0;
};

// The base's up axis in the corner frame for a camera at `pose` on `base_camera`'s mount:
// its horizontal components (x, y), each the sine of the base's tip towards that axis.
Eigen::Vector2d BaseTipInCornerFrame(const CornerPose& pose, const RigidTransform& base_camera);
// Its derivative by (x, y, pan, tilt, swing) (zero by x and y).
Eigen::Matrix<double, 2, 5> BaseTipJacobian(const CornerPose& pose,
                                            const RigidTransform& base_camera);

// `covariance`: of (x, y, pan, tilt, swing) as solved (m^2, rad^2). `base_camera`: the mount
// (only its rotation is used). An iterated linear Gaussian update: the maximum a posteriori
// pose under the pose's Gaussian and the level's, for tips small enough to be linear.
LevelledCornerPose LevelWithMount(const CornerPose& pose,
                                  const Eigen::Matrix<double, 5, 5>& covariance,
                                  const RigidTransform& base_camera, double level_sigma_rad);

}  // namespace monocle
