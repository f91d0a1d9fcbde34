// Seeded random corner views shared by corner tests and benchmarks.
#pragma once

#include <algorithm>
#include <array>
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

// Visible length of each corner edge (X, Y, Z) in the image, pixels: from the corner along
// the edge's projection until it leaves the image (or the edge ends at `room_m`).
inline std::array<double, 3> VisibleEdgeLengthsPx(const CornerPose& pose, const CameraIntrinsics& k,
                                                  double room_m = 8.0) {
  std::array<double, 3> length{};
  const Eigen::Vector3d c = CornerToCamera(pose, Eigen::Vector3d::Zero());
  if (c.z() <= 0) return length;
  const Eigen::Vector2d corner = NormalizedToPixel(k, c.head<2>() / c.z());
  for (int axis = 0; axis < 3; ++axis) {
    for (double t = 0.005; t <= room_m; t += 0.005) {
      const Eigen::Vector3d p = CornerToCamera(pose, t * Eigen::Vector3d::Unit(axis));
      if (p.z() <= 0.05) break;
      const Eigen::Vector2d px = NormalizedToPixel(k, p.head<2>() / p.z());
      if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1) break;
      length[axis] = (px - corner).norm();
    }
  }
  return length;
}

// A view as a robot meets it: the corner anywhere in the frame, 15 px from the border or
// more, every edge visible for at least 80 px; with `short_edge` one edge is a fifth of the
// image's width or less.
inline std::optional<CornerPose> RandomRealisticCornerPose(std::mt19937_64& rng,
                                                           const CameraIntrinsics& k,
                                                           bool short_edge) {
  for (int attempt = 0; attempt < 2000; ++attempt) {
    const auto p = RandomCornerPose(rng, k, /*margin_px=*/15);
    if (!p) continue;
    const auto lengths = VisibleEdgeLengthsPx(*p, k);
    const double shortest = *std::min_element(lengths.begin(), lengths.end());
    if (shortest < 80) continue;
    if (short_edge != (shortest <= 0.2 * k.width_px)) continue;
    return p;
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
