#include "service/geometry/base_in_corner.h"

#include <cmath>

namespace monocle {
namespace {

struct PlacedBase {
  RigidTransform corner_base;
  double heading_rad = 0;
};

PlacedBase PlaceBase(const CornerPose& pose, const RigidTransform& base_camera) {
  RigidTransform corner_camera;
  corner_camera.rotation = Eigen::Quaterniond(RotationCameraFromCorner(pose).transpose());
  corner_camera.translation = CameraPosition(pose);
  PlacedBase out;
  out.corner_base = BaseInParent(corner_camera, base_camera);
  const Eigen::Vector3d forward = out.corner_base.rotation * Eigen::Vector3d::UnitX();
  out.heading_rad = std::atan2(forward.y(), forward.x());
  return out;
}

}  // namespace

BaseInCorner BaseInCornerFrame(const CornerPose& pose,
                               const Eigen::Matrix<double, 5, 5>& covariance,
                               const RigidTransform& base_camera) {
  const PlacedBase placed = PlaceBase(pose, base_camera);
  BaseInCorner out;
  out.corner_base = placed.corner_base;
  out.heading_rad = placed.heading_rad;
  // First-order propagation by central differences over (x, y, pan, tilt, swing).
  Eigen::Matrix<double, 3, 5> jacobian;
  for (int k = 0; k < 5; ++k) {
    const double step = k < 2 ? 1e-6 * std::max(pose.z_m, 1.0) : 1e-7;
    Eigen::Matrix<double, 5, 1> change = Eigen::Matrix<double, 5, 1>::Zero();
    change[k] = step;
    const PlacedBase a = PlaceBase(MovedBy(pose, change), base_camera);
    const PlacedBase b = PlaceBase(MovedBy(pose, -change), base_camera);
    jacobian.col(k) << (a.corner_base.translation.head<2>() - b.corner_base.translation.head<2>()) /
                           (2 * step),
        std::remainder(a.heading_rad - b.heading_rad, 2 * M_PI) / (2 * step);
  }
  const Eigen::Matrix3d c = jacobian * covariance * jacobian.transpose();
  out.covariance = 0.5 * (c + c.transpose());  // exactly symmetric, as published
  return out;
}

}  // namespace monocle
