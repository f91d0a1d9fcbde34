#include "camera/render/floor_renderer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

#include "camera/render/board_renderer.h"
#include "camera/render/reference_camera.h"
#include "service/geometry/floor_calibration.h"

namespace monocle {
namespace {

constexpr double kWhite = 225, kBlack = 25, kFloor = 120, kWall = 165;

// Distance along the ray to the first box face it hits, or infinity; `shade` is the face's
// grey level.
double IntersectBoxes(const std::vector<FloorBox>& boxes, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& dir, double* shade) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& box : boxes) {
    const Eigen::Vector3d lo(box.center_m.x() - box.size_m.x() / 2,
                             box.center_m.y() - box.size_m.y() / 2, 0);
    const Eigen::Vector3d hi(box.center_m.x() + box.size_m.x() / 2,
                             box.center_m.y() + box.size_m.y() / 2, box.height_m);
    double t_near = -std::numeric_limits<double>::infinity(),
           t_far = std::numeric_limits<double>::infinity();
    int axis_near = -1;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir[a]) < 1e-15) {
        if (origin[a] < lo[a] || origin[a] > hi[a])
          t_near = std::numeric_limits<double>::infinity();
        continue;
      }
      double t0 = (lo[a] - origin[a]) / dir[a], t1 = (hi[a] - origin[a]) / dir[a];
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_near) {
        t_near = t0;
        axis_near = a;
      }
      t_far = std::min(t_far, t1);
    }
    if (t_near <= t_far && t_near > 0 && t_near < best) {
      best = t_near;
      *shade = axis_near == 2 ? 205.0 : (axis_near == 0 ? 150.0 : 95.0);
    }
  }
  return best;
}

}  // namespace

Eigen::Vector2d CenteredBoardOrigin(const FloorPose& pose, int cols, int rows, double square_m) {
  // Optical axis in the robot frame, from the camera at (0, 0, h).
  const Eigen::Vector3d axis =
      reference::RotationCameraFromRobot(pose).transpose() * Eigen::Vector3d::UnitZ();
  Eigen::Vector2d center(0, 2);
  if (axis.z() < -1e-3) {
    const double t = pose.height_m / -axis.z();
    center = Eigen::Vector2d(axis.x() * t, axis.y() * t);
  }
  const Eigen::Vector3d half =
      BoardToRobot(pose.yaw_rad, Eigen::Vector2d::Zero(),
                   Eigen::Vector2d((cols - 1) * square_m / 2, (rows - 1) * square_m / 2));
  return center - half.head<2>();
}

cv::Mat RenderFloorScene(const CameraIntrinsics& k, const FloorPose& pose,
                         const FloorScene& scene) {
  const int w = k.width_px, h = k.height_px;
  const Eigen::Matrix3d r_robot_camera = reference::RotationCameraFromRobot(pose).transpose();
  const Eigen::Vector3d camera_center(0, 0, pose.height_m);
  const double s = scene.square_m;
  const double ca = std::cos(pose.yaw_rad), sa = std::sin(pose.yaw_rad);

  // Board coordinates of the floor point under every pixel centre (NaN: no floor there),
  // and the pixel's shade if a box hides the floor.
  cv::Mat board_x(h, w, CV_64F), board_y(h, w, CV_64F), box_shade(h, w, CV_64F, cv::Scalar(-1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const cv::Mat rays = reference::UndistortedPixelGrid(k);
  for (int v = 0; v < h; ++v) {
    auto* bx = board_x.ptr<double>(v);
    auto* by = board_y.ptr<double>(v);
    auto* shade_row = box_shade.ptr<double>(v);
    const auto* ray = rays.ptr<cv::Point2d>(v);
    for (int u = 0; u < w; ++u) {
      bx[u] = by[u] = nan;
      const Eigen::Vector3d dir = r_robot_camera * Eigen::Vector3d(ray[u].x, ray[u].y, 1.0);
      double shade = 0;
      const double t_box = scene.boxes.empty()
                               ? std::numeric_limits<double>::infinity()
                               : IntersectBoxes(scene.boxes, camera_center, dir, &shade);
      const double t_floor =
          dir.z() < -1e-9 ? pose.height_m / -dir.z() : std::numeric_limits<double>::infinity();
      if (t_box < t_floor) {
        shade_row[u] = shade;
        continue;
      }
      if (!std::isfinite(t_floor)) continue;
      const Eigen::Vector2d p =
          (camera_center + t_floor * dir).head<2>() - scene.board_origin_robot_m;
      // Inverse of eq. (10).
      bx[u] = ca * p.x() - sa * p.y();
      by[u] = sa * p.x() + ca * p.y();
    }
  }

  cv::Mat image(h, w, CV_8UC1);
  cv::Mat noise(h, w, CV_64F, cv::Scalar(0));
  if (scene.noise_sigma > 0) {
    cv::RNG rng(scene.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, scene.noise_sigma);
  }
  const CheckerPattern pattern{scene.board_cols, scene.board_rows, s, kWhite, kBlack};
  for (int v = 0; v < h; ++v) {
    const auto* bx = board_x.ptr<double>(v);
    const auto* by = board_y.ptr<double>(v);
    const auto* shade_row = box_shade.ptr<double>(v);
    const auto* noise_row = noise.ptr<double>(v);
    auto* out = image.ptr<uint8_t>(v);
    for (int u = 0; u < w; ++u) {
      double value;
      if (shade_row[u] >= 0) {
        value = shade_row[u];
      } else if (std::isnan(bx[u])) {
        value = kWall;
      } else {
        // Footprint half-widths from central differences with neighbouring pixels.
        auto diff = [&](const cv::Mat& m, int du, int dv) {
          const int u0 = std::max(u - du, 0), u1 = std::min(u + du, w - 1);
          const int v0 = std::max(v - dv, 0), v1 = std::min(v + dv, h - 1);
          const double a = m.at<double>(v0, u0), b = m.at<double>(v1, u1);
          const double span = (du ? u1 - u0 : v1 - v0);
          if (std::isnan(a) || std::isnan(b) || span == 0) return 0.0;
          return (b - a) / span;
        };
        const double wx = 0.5 * (std::abs(diff(board_x, 1, 0)) + std::abs(diff(board_x, 0, 1)));
        const double wy = 0.5 * (std::abs(diff(board_y, 1, 0)) + std::abs(diff(board_y, 0, 1)));
        value = CheckerValue(pattern, bx[u], by[u], wx, wy, kFloor);
      }
      out[u] = cv::saturate_cast<uint8_t>(value + noise_row[u]);
    }
  }
  return image;
}

}  // namespace monocle
