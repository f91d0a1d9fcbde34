// Floor measurement model of Xu et al. 2017, generalised to a camera roll.
// Pure geometry: Eigen only, no I/O.
//
// Robot frame W (the paper's): origin O_w on the floor vertically below the optical
// centre, X_w parallel to the camera's X_c (the image's horizontal axis), Z_w up,
// Y_w = Z_w x X_w (forward). Metres.
//
// Camera: p_c = R_roll * R_pitch * p_w + R_roll * (0, h sin(theta), -h cos(theta)), with
// R_pitch the paper's eq. (1) and R_roll = [[cos r, -sin r, 0], [sin r, cos r, 0], [0, 0, 1]]
// a rotation about the optical axis. With roll = 0 this is exactly eq. (2).
//
// Chessboard frame P (eq. 10): x_w = x_p cos(a) + y_p sin(a) + t_x,
//                               y_w = -x_p sin(a) + y_p cos(a) + t_y.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <ostream>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"

namespace monocle {

struct FloorPose {
  double height_m = 0;   // h
  double pitch_rad = 0;  // theta
  double yaw_rad = 0;    // alpha (board x axis against X_w); does not affect measurement
  double roll_rad = 0;   // rotation about the optical axis
};

std::ostream& operator<<(std::ostream& os, const FloorPose& p);

// Covariance of (height, pitch, yaw, roll).
using FloorCovariance = Eigen::Matrix4d;

// Rotation and translation taking robot-frame points into the camera frame.
Eigen::Matrix3d RotationCameraFromRobot(const FloorPose& pose);
Eigen::Vector3d TranslationCameraFromRobot(const FloorPose& pose);

// Robot-frame point -> camera frame.
Eigen::Vector3d RobotToCamera(const FloorPose& pose, const Eigen::Vector3d& p_robot_m);

// Robot-frame point -> pixel; empty when the point is behind the camera.
std::optional<Eigen::Vector2d> ProjectRobotPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                                 const Eigen::Vector3d& p_robot_m);

// Camera-frame normalized coordinates -> the paper's (x_1c, y_1c), i.e. with roll removed.
Eigen::Vector2d RemoveRoll(double roll_rad, const Eigen::Vector2d& normalized);

// A measured point with its 1-sigma uncertainty (metres, robot frame).
struct FloorMeasurement {
  Eigen::Vector3d p_robot_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d Sigma() const { return covariance.diagonal().cwiseSqrt(); }
};

std::ostream& operator<<(std::ostream& os, const FloorMeasurement& m);

// Everything a measurement's 1 sigma stands on, propagated to first order:
//   cov(p) = [J_pose J_k] [[P, C], [C^T, K]] [J_pose J_k]^T + sigma_px^2 J_px J_px^T
// with P the floor pose covariance, K the intrinsics' (camera_model.h's parameter order) and
// C their cross-covariance: a floor pose fitted with slightly wrong intrinsics partly
// compensates for them, so the two errors are correlated and C matters.
struct MeasurementNoise {
  FloorCovariance pose_covariance = FloorCovariance::Zero();
  double pixel_sigma_px = 0;  // isotropic noise of every pixel coordinate
  IntrinsicsCovariance intrinsics_covariance = IntrinsicsCovariance::Zero();
  // cov((height, pitch, yaw, roll), intrinsics)
  Eigen::Matrix<double, 4, kNumIntrinsicParams> pose_intrinsics_covariance =
      Eigen::Matrix<double, 4, kNumIntrinsicParams>::Zero();
};

// Eq. (5): the floor point (x, y, 0) seen at `floor_px`.
Result<FloorMeasurement> MeasureFloorPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                           const MeasurementNoise& noise,
                                           const Eigen::Vector2d& floor_px);

// Eq. (7): the point seen at `top_px` standing vertically above its foot, the floor point
// seen at `foot_px`; x and y are those of the foot. A height below zero by more than
// kVerticalPointSigmas of its own 1 sigma is refused (kOutOfRange): the top is below its foot.
inline constexpr double kVerticalPointSigmas = 3.0;
Result<FloorMeasurement> MeasureVerticalPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                              const MeasurementNoise& noise,
                                              const Eigen::Vector2d& foot_px,
                                              const Eigen::Vector2d& top_px);

// Same as above without uncertainty, for callers that need only the point (faster).
Result<Eigen::Vector3d> FloorPointFromPixel(const CameraIntrinsics& k, const FloorPose& pose,
                                            const Eigen::Vector2d& floor_px);

}  // namespace monocle
