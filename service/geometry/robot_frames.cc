#include "service/geometry/robot_frames.h"

namespace monocle {

RigidTransform Compose(const RigidTransform& a_b, const RigidTransform& b_c) {
  return {(a_b.rotation * b_c.rotation).normalized(),
          a_b.translation + a_b.rotation * b_c.translation};
}

RigidTransform Inverse(const RigidTransform& a_b) {
  const Eigen::Quaterniond r = a_b.rotation.conjugate();
  return {r, -(r * a_b.translation)};
}

RigidTransform BaseInParent(const RigidTransform& parent_camera,
                            const RigidTransform& base_camera) {
  return Compose(parent_camera, Inverse(base_camera));
}

}  // namespace monocle
