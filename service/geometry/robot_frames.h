// The robot's pose from the camera's: a camera fixed on the robot (its mount, T_base_camera)
// seen at T_parent_camera puts the robot's base at T_parent_base = T_parent_camera *
// T_base_camera^-1. Pure geometry, for tf (service/server/ros_topics.cc).
#pragma once

#include <Eigen/Geometry>

namespace monocle {

struct RigidTransform {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // child axes in the parent
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();         // child origin in the parent
};

RigidTransform Compose(const RigidTransform& a_b, const RigidTransform& b_c);
RigidTransform Inverse(const RigidTransform& a_b);
// T_parent_base from T_parent_camera and the mount T_base_camera.
RigidTransform BaseInParent(const RigidTransform& parent_camera, const RigidTransform& base_camera);

}  // namespace monocle
