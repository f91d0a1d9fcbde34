// The robot's base in the corner frame, from the camera's corner pose and its mount:
// T_corner_base = T_corner_camera * T_base_camera^-1, as /tf shows it without a room map;
// with the covariance of the base's place on the floor's plane and its heading, propagated
// to first order from the corner pose's. Pure geometry.
#pragma once

#include <Eigen/Core>

#include "service/geometry/corner_pose.h"
#include "service/geometry/robot_frames.h"

namespace monocle {

struct BaseInCorner {
  RigidTransform corner_base;  // the base frame in the corner frame (whose Z points down)
  // The base's +x axis on the ceiling plane, radians from the corner's X towards its Y.
  double heading_rad = 0;
  // Of (x, y, heading): the base origin's corner-frame X and Y (metres) and heading_rad.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();

  double x_m() const { return corner_base.translation.x(); }
  double y_m() const { return corner_base.translation.y(); }
  Eigen::Vector3d Sigma() const { return covariance.diagonal().cwiseSqrt(); }
};

// `covariance`: of the pose's (x, y, pan, tilt, swing), m^2 and rad^2 (its z, the ceiling
// distance, is given). `base_camera`: the mount, the optical frame in the base frame.
BaseInCorner BaseInCornerFrame(const CornerPose& pose,
                               const Eigen::Matrix<double, 5, 5>& covariance,
                               const RigidTransform& base_camera);

}  // namespace monocle
