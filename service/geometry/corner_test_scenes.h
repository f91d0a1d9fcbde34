// Seeded random corner views shared by corner tests and benchmarks.
#pragma once

#include <cmath>
#include <numbers>
#include <optional>
#include <random>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"

namespace monocle::testing {

// Pose over the range: camera 0.3-6 m from each wall, ceiling 0.5-3 m above, tilt
// 10-85 degrees, swing +-30 degrees, pan towards the corner give or take what keeps the
// corner inside a 1280x1024 f=1600 image, away from the border by `margin_px`.
inline std::optional<CornerPose> RandomCornerPose(std::mt19937_64& rng, const CameraIntrinsics& k,
                                                  double margin_px = 50) {
  constexpr double kDeg = std::numbers::pi / 180;
  std::uniform_real_distribution<double> wall(0.3, 6.0), ceiling(0.5, 3.0),
      tilt(10 * kDeg, 85 * kDeg), swing(-30 * kDeg, 30 * kDeg), pan_jitter(-25 * kDeg, 25 * kDeg);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    CornerPose p{wall(rng), wall(rng), ceiling(rng), 0, tilt(rng), swing(rng)};
    // Horizontal view direction (-sin psi, cos psi) towards the corner at the origin.
    p.pan_rad = std::atan2(p.x_m, -p.y_m) + pan_jitter(rng);
    const Eigen::Vector3d c = CornerToCamera(p, Eigen::Vector3d::Zero());
    if (c.z() <= 0.05) continue;
    const Eigen::Vector2d px = NormalizedToPixel(k, c.head<2>() / c.z());
    if (px.x() < margin_px || px.y() < margin_px || px.x() > k.width_px - margin_px ||
        px.y() > k.height_px - margin_px) {
      continue;
    }
    return Canonical(p);
  }
  return std::nullopt;
}

// Exact image rays of the three axes from a pose, listed in `order` (a permutation of the
// axes) so tests can check labelling.
inline std::array<ObservedRay, 3> ExactRays(const CornerPose& pose,
                                            const std::array<int, 3>& order) {
  std::array<ObservedRay, 3> rays;
  const Eigen::Vector3d c = CornerToCamera(pose, Eigen::Vector3d::Zero());
  const double step = 1e-3 * CameraPosition(pose).norm();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = CornerToCamera(pose, step * Eigen::Vector3d::Unit(order[k]));
    rays[k].corner = c.head<2>() / c.z();
    rays[k].direction = (a.head<2>() / a.z() - rays[k].corner).normalized();
  }
  return rays;
}

}  // namespace monocle::testing
