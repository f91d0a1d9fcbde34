#include "service/geometry/pose_covariance.h"

#include <Eigen/Geometry>

namespace monocle {

Eigen::Vector3d RotationChange(const CornerPose& pose, const Eigen::Vector3d& d_angles_rad) {
  CornerPose moved = pose;
  moved.pan_rad += d_angles_rad[0];
  moved.tilt_rad += d_angles_rad[1];
  moved.swing_rad += d_angles_rad[2];
  // R_corner_camera = R_camera_corner^T.
  const Eigen::Matrix3d before = RotationCameraFromCorner(pose).transpose();
  const Eigen::Matrix3d after = RotationCameraFromCorner(moved).transpose();
  const Eigen::AngleAxisd change(after * before.transpose());
  return change.angle() * change.axis();
}

Eigen::Matrix<double, 6, 6> RosPoseCovariance(const CornerPose& pose,
                                              const Eigen::Matrix<double, 5, 5>& covariance) {
  Eigen::Matrix<double, 6, 5> j = Eigen::Matrix<double, 6, 5>::Zero();
  j(0, 0) = 1;  // x
  j(1, 1) = 1;  // y; row 2 (z) stays zero
  constexpr double kStep = 1e-6;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[a] = kStep;
    j.block<3, 1>(3, 2 + a) = (RotationChange(pose, d) - RotationChange(pose, -d)) / (2 * kStep);
  }
  const Eigen::Matrix<double, 6, 6> ros = j * covariance * j.transpose();
  // Exactly symmetric: J C J^T rounds its two triangles differently, and consumers (and
  // our test) check the 36 numbers as published.
  return 0.5 * (ros + ros.transpose());
}

}  // namespace monocle
