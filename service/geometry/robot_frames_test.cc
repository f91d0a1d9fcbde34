// Round trips of the robot-frame composition: a point seen through the camera lands where the
// base's pose puts it.
#include "service/geometry/robot_frames.h"

#include <gtest/gtest.h>

#include <random>

namespace monocle {
namespace {

RigidTransform Random(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  return {Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized(),
          Eigen::Vector3d(n(rng), n(rng), n(rng))};
}

Eigen::Vector3d Apply(const RigidTransform& t, const Eigen::Vector3d& p) {
  return t.rotation * p + t.translation;
}

TEST(RobotFramesTest, BaseInParentMapsPointsLikeTheCameraDoes) {
  std::mt19937 rng(7);
  for (int i = 0; i < 100; ++i) {
    const RigidTransform parent_base = Random(rng), base_camera = Random(rng);
    // The camera's pose as the corner solver would report it for this robot pose.
    const RigidTransform parent_camera = Compose(parent_base, base_camera);
    const RigidTransform recovered = BaseInParent(parent_camera, base_camera);
    EXPECT_LT((recovered.translation - parent_base.translation).norm(), 1e-12);
    EXPECT_LT(recovered.rotation.angularDistance(parent_base.rotation), 1e-12);
    // A point in camera coordinates, through the camera or through base and mount.
    const Eigen::Vector3d p_camera(0.3, -0.2, 2.0);
    EXPECT_LT(
        (Apply(parent_camera, p_camera) - Apply(recovered, Apply(base_camera, p_camera))).norm(),
        1e-12);
  }
}

TEST(RobotFramesTest, InverseUndoes) {
  std::mt19937 rng(8);
  const RigidTransform t = Random(rng);
  const RigidTransform identity = Compose(t, Inverse(t));
  EXPECT_LT(identity.translation.norm(), 1e-12);
  EXPECT_LT(identity.rotation.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
}

}  // namespace
}  // namespace monocle
