#include "camera/render/room_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "camera/render/photograph.h"
#include "camera/render/reference_camera.h"
#include "camera/render/supersampled_view.h"

namespace monocle {
namespace {

// Surfaces: 0 ceiling, 1 floor, 2 + i the wall from outline[i] to outline[i + 1].
constexpr int kCeiling = 0, kFloor = 1, kFirstWall = 2;

struct Hit {
  int surface = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double along_wall_m = 0;
};

Hit CastRay(const MapRoom& room, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = std::numeric_limits<double>::infinity();
  Hit hit;
  const double h = room.ceiling_height_m;
  if (d.z() > 1e-12) {
    best = (h - o.z()) / d.z();
    hit.surface = kCeiling;
  } else if (d.z() < -1e-12) {
    best = -o.z() / d.z();
    hit.surface = kFloor;
  }
  const auto& outline = room.outline_m;
  for (size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d a = outline[i], b = outline[(i + 1) % outline.size()];
    const Eigen::Vector2d e = b - a;
    // o.xy + t d.xy = a + s e.
    const double det = d.x() * (-e.y()) - d.y() * (-e.x());
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector2d r = a - o.head<2>();
    const double t = (r.x() * (-e.y()) - r.y() * (-e.x())) / det;
    const double s = (d.x() * r.y() - d.y() * r.x()) / det;
    if (t <= 0 || t >= best || s < 0 || s > 1) continue;
    const double z = o.z() + t * d.z();
    if (z < 0 || z > h) continue;
    best = t;
    hit.surface = kFirstWall + static_cast<int>(i);
    hit.along_wall_m = s * e.norm();
  }
  hit.point = o + best * d;
  return hit;
}

// Walls facing along the map's x get one paint, walls facing along y the other: two walls
// meeting at a right angle always differ.
bool FacesX(const MapRoom& room, int wall) {
  const auto& o = room.outline_m;
  const Eigen::Vector2d e = o[(wall + 1) % o.size()] - o[wall];
  return std::abs(e.y()) > std::abs(e.x());  // runs along y, so its normal is along x
}

double Shade(const MapRoom& room, const Hit& hit, const RoomScene& scene) {
  if (hit.surface < 0) return 0;
  const int wall = hit.surface - kFirstWall;
  if (!scene.realistic) {
    if (hit.surface == kCeiling) return 205;
    if (hit.surface == kFloor) return 70;
    return FacesX(room, wall) ? 100 : 150;
  }
  const RealisticLook& l = *scene.realistic;
  const Eigen::Vector2d origin = room.outline_m.front();
  if (hit.surface == kCeiling) {
    const Eigen::Vector2d in_plane = hit.point.head<2>() - origin;
    return l.ceiling_grey * std::clamp(1 + l.shading_per_m[0].dot(in_plane), 0.5, 1.5);
  }
  if (hit.surface == kFloor) return 0.6 * l.ceiling_grey;
  const bool faces_x = FacesX(room, wall);
  const double base = faces_x ? l.wall_x0_grey : l.wall_y0_grey;
  const Eigen::Vector2d in_plane(hit.along_wall_m, room.ceiling_height_m - hit.point.z());
  const Eigen::Vector2d& gradient = l.shading_per_m[faces_x ? 1 : 2];
  return base * std::clamp(1 + gradient.dot(in_plane), 0.5, 1.5);
}

}  // namespace

cv::Mat RenderRoomView(const CameraIntrinsics& k, const MapRoom& room,
                       const Eigen::Isometry3d& map_from_camera, const RoomScene& scene) {
  const Eigen::Matrix3d rotation = map_from_camera.linear();
  const Eigen::Vector3d origin = map_from_camera.translation();
  cv::Mat value = RenderSupersampledView(k, [&](const cv::Point2d& n, int32_t* surface) {
    const Hit hit = CastRay(room, origin, rotation * Eigen::Vector3d(n.x, n.y, 1));
    *surface = hit.surface;
    return Shade(room, hit, scene);
  });
  if (scene.realistic) {
    const RealisticLook& l = *scene.realistic;
    return Photograph(value,
                      PhotoEffects{l.vignetting, l.hotspot_px, l.hotspot_radius_px, l.hotspot_gain,
                                   l.blur_sigma_px, l.noise_sigma, l.jpeg_quality},
                      scene.seed);
  }
  cv::Mat out;
  value.convertTo(out, CV_8U);
  return out;
}

}  // namespace monocle
