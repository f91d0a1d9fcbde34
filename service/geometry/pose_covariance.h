// A corner pose's uncertainty in the form ROS's geometry_msgs/PoseWithCovariance carries it.
// Pure geometry: Eigen only.
#pragma once

#include <Eigen/Core>

#include "service/geometry/corner_pose.h"

namespace monocle {

// ROS's 6x6 covariance of (x, y, z, rotation about the parent frame's X, Y, Z) for the camera
// at `pose` in the corner frame, from monocle's 5x5 covariance of (x, y, pan, tilt, swing).
// z is the ceiling distance the user gave, not measured: no variance. The rotation part is
// that of the small rotation vector phi with
//   R_corner_camera(pan + d_pan, tilt + d_tilt, swing + d_swing) = exp([phi]x) R_corner_camera,
// to first order phi = J (d_pan, d_tilt, d_swing), cov(phi) = J C J^T.
Eigen::Matrix<double, 6, 6> RosPoseCovariance(const CornerPose& pose,
                                              const Eigen::Matrix<double, 5, 5>& covariance);

// The rotation vector phi above for a given change of the angles (exact, for tests).
Eigen::Vector3d RotationChange(const CornerPose& pose, const Eigen::Vector3d& d_angles_rad);

}  // namespace monocle
