#include "service/geometry/mount_level.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace monocle {
namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;

}  // namespace

Eigen::Vector2d BaseTipInCornerFrame(const CornerPose& pose, const RigidTransform& base_camera) {
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(pose).transpose();
  const Eigen::Matrix3d base_from_camera = base_camera.rotation.toRotationMatrix();
  const Eigen::Vector3d up_in_corner = corner_from_camera * base_from_camera.transpose().col(2);
  return up_in_corner.head<2>();
}

// By central differences.
Eigen::Matrix<double, 2, 5> BaseTipJacobian(const CornerPose& pose, const RigidTransform& mount) {
  constexpr double kStepRad = 1e-6;
  Eigen::Matrix<double, 2, 5> jacobian = Eigen::Matrix<double, 2, 5>::Zero();
  for (int i = 2; i < 5; ++i) {
    const Vector5d step = Vector5d::Unit(i) * kStepRad;
    jacobian.col(i) = (BaseTipInCornerFrame(MovedBy(pose, step), mount) -
                       BaseTipInCornerFrame(MovedBy(pose, -step), mount)) /
                      (2 * kStepRad);
  }
  return jacobian;
}

LevelledCornerPose LevelWithMount(const CornerPose& pose,
                                  const Eigen::Matrix<double, 5, 5>& covariance,
                                  const RigidTransform& base_camera, double level_sigma_rad) {
  LevelledCornerPose out{pose, covariance, 0};
  {
    const Eigen::Matrix3d corner_from_base = RotationCameraFromCorner(pose).transpose() *
                                             base_camera.rotation.toRotationMatrix().transpose();
    // Level: the base's up axis along -Z.
    out.level_error_rad = std::acos(std::clamp(-corner_from_base(2, 2), -1.0, 1.0));
  }
  // Iterated update (Gauss-Newton on |step|^2 in the covariance's metric plus |tip|^2 in the
  // level's): the tip is nearly linear in the angles, and three rounds take a pose tipped 1
  // degree back to the truth within 1e-6 rad (mount_level_test).
  const Eigen::Matrix2d level_covariance =
      level_sigma_rad * level_sigma_rad * Eigen::Matrix2d::Identity();
  Vector5d step = Vector5d::Zero();
  Eigen::Matrix<double, 5, 2> gain = Eigen::Matrix<double, 5, 2>::Zero();
  Eigen::Matrix<double, 2, 5> jacobian = Eigen::Matrix<double, 2, 5>::Zero();
  {
    const Eigen::Matrix<double, 2, 5> at_pose = BaseTipJacobian(pose, base_camera);
    const Eigen::Vector2d tip = BaseTipInCornerFrame(pose, base_camera);
    out.tip_mahalanobis2 =
        tip.dot((at_pose * covariance * at_pose.transpose() + level_covariance).ldlt().solve(tip));
  }
  for (int round = 0; round < 3; ++round) {
    const CornerPose at = MovedBy(pose, step);
    jacobian = BaseTipJacobian(at, base_camera);
    const Eigen::Matrix2d innovation =
        jacobian * covariance * jacobian.transpose() + level_covariance;
    gain = covariance * jacobian.transpose() * innovation.inverse();
    // The tip predicted linearly from the solved pose, set to zero.
    const Eigen::Vector2d tip_at_pose = BaseTipInCornerFrame(at, base_camera) - jacobian * step;
    step = -gain * tip_at_pose;
  }
  out.pose = Canonical(MovedBy(pose, step));
  out.covariance = covariance - gain * jacobian * covariance;
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
  return out;
}

}  // namespace monocle
