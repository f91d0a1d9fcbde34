#include "camera/render/corner_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace monocle {
namespace {

enum Material : uint8_t {
  kNone,
  kCeiling,
  kWallY0,
  kWallX0,
  kFloor,
  kFarWall,
  kLamp,
  kFrame,
  kFixture,
  kPicture
};

struct Hit {
  Material material = kNone;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

// Rectangles drawn on surfaces (clutter), as ranges of the surface's two in-plane axes.
struct Decal {
  Material surface;
  double a0, a1, b0, b1;
  Material material;
};

// Placed relative to the corner, away from the three edges so the Y stays visible but
// close enough to be in view and to cross the search windows of a detector.
constexpr std::array<Decal, 7> kDecals{{
    {kCeiling, 1.2, 1.9, 0.9, 1.25, kLamp},      // x, y: a bright lamp
    {kCeiling, 0.35, 3.5, 0.55, 0.6, kFixture},  // a long thin fixture, parallel to X
    {kWallX0, 1.4, 1.5, 0.45, 2.8, kFrame},      // y, z: door frame, left jamb
    {kWallX0, 2.3, 2.4, 0.45, 2.8, kFrame},      // right jamb
    {kWallX0, 1.4, 2.4, 0.45, 0.55, kFrame},     // lintel
    {kWallY0, 0.8, 1.6, 0.5, 1.1, kPicture},     // x, z: a picture
    {kCeiling, 0.5, 0.54, 1.6, 4.0, kFixture},   // a cable, parallel to Y
}};

Hit CastRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const CornerScene& scene,
            bool clutter) {
  const double size = scene.room_size_m, height = scene.room_height_m;
  double best = std::numeric_limits<double>::infinity();
  Hit hit;
  auto consider = [&](int axis, double plane, Material m) {
    if (std::abs(dir[axis]) < 1e-15) return;
    const double t = (plane - origin[axis]) / dir[axis];
    if (t <= 0 || t >= best) return;
    const Eigen::Vector3d p = origin + t * dir;
    for (int a = 0; a < 3; ++a) {
      if (a == axis) continue;
      const double hi = a == 2 ? height : size;
      if (p[a] < -1e-9 || p[a] > hi + 1e-9) return;
    }
    best = t;
    hit = {m, p};
  };
  consider(2, 0.0, kCeiling);
  consider(1, 0.0, kWallY0);
  consider(0, 0.0, kWallX0);
  consider(2, height, kFloor);
  consider(0, size, kFarWall);
  consider(1, size, kFarWall);
  if (clutter && hit.material != kNone) {
    for (const auto& d : kDecals) {
      if (d.surface != hit.material) continue;
      double a = 0, b = 0;
      if (hit.material == kCeiling) a = hit.point.x(), b = hit.point.y();
      if (hit.material == kWallX0) a = hit.point.y(), b = hit.point.z();
      if (hit.material == kWallY0) a = hit.point.x(), b = hit.point.z();
      if (a >= d.a0 && a <= d.a1 && b >= d.b0 && b <= d.b1) hit.material = d.material;
    }
  }
  return hit;
}

double Shade(const Hit& hit, const CornerScene& scene) {
  double base = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  switch (hit.material) {
    case kCeiling:
      base = 205;
      normal = Eigen::Vector3d::UnitZ();
      break;
    case kWallY0:
      base = 150;
      normal = Eigen::Vector3d::UnitY();
      break;
    case kWallX0:
      base = 100;
      normal = Eigen::Vector3d::UnitX();
      break;
    case kFloor:
      base = 70;
      normal = -Eigen::Vector3d::UnitZ();
      break;
    case kFarWall:
      base = 120;
      break;
    case kLamp:
      return 252;
    case kFrame:
      return 45;
    case kFixture:
      return 60;
    case kPicture:
      return 230;
    case kNone:
      return 0;
  }
  if (!scene.uneven_lighting) return base;
  // A lamp below the ceiling near the corner: Lambertian falloff, plus a soft texture.
  const Eigen::Vector3d lamp(1.5, 1.1, 1.0);
  const Eigen::Vector3d to_lamp = lamp - hit.point;
  const double cosine = std::max(0.0, normal.dot(to_lamp.normalized()));
  const double light = 0.7 + 0.5 * cosine / (1 + to_lamp.squaredNorm() / 4);
  const double texture = 1 + 0.04 * std::sin(7.3 * hit.point.x() + 3.1 * hit.point.y()) *
                                 std::sin(5.7 * hit.point.z() + 2.3 * hit.point.x());
  return std::min(base * light * texture, 250.0);
}

}  // namespace

cv::Mat RenderCornerScene(const CameraIntrinsics& k, const CornerPose& pose,
                          const CornerScene& scene) {
  const int w = k.width_px, h = k.height_px;
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(pose).transpose();
  const Eigen::Vector3d origin = CameraPosition(pose);
  cv::Mat value(h, w, CV_32F), material(h, w, CV_8U);
  for (int v = 0; v < h; ++v) {
    auto* val = value.ptr<float>(v);
    auto* mat = material.ptr<uint8_t>(v);
    for (int u = 0; u < w; ++u) {
      const auto n = PixelToNormalized(k, Eigen::Vector2d(u, v));
      if (!n) {
        val[u] = 0;
        mat[u] = kNone;
        continue;
      }
      const Hit hit = CastRay(origin, corner_from_camera * n->homogeneous(), scene, scene.clutter);
      val[u] = static_cast<float>(Shade(hit, scene));
      mat[u] = hit.material;
    }
  }
  // Supersample 4x4 where a neighbour has another material.
  cv::Mat out(h, w, CV_8U);
  cv::Mat noise(h, w, CV_32F, cv::Scalar(0));
  if (scene.noise_sigma > 0) {
    cv::RNG rng(scene.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, scene.noise_sigma);
  }
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const uint8_t m = material.at<uint8_t>(v, u);
      bool boundary = false;
      for (int dv = -1; dv <= 1 && !boundary; ++dv) {
        for (int du = -1; du <= 1 && !boundary; ++du) {
          const int uu = std::clamp(u + du, 0, w - 1), vv = std::clamp(v + dv, 0, h - 1);
          boundary = material.at<uint8_t>(vv, uu) != m;
        }
      }
      double sum = value.at<float>(v, u);
      if (boundary) {
        Eigen::Matrix2d j;
        const auto n = PixelToNormalized(k, Eigen::Vector2d(u, v), &j);
        if (n) {
          sum = 0;
          for (int sy = 0; sy < 4; ++sy) {
            for (int sx = 0; sx < 4; ++sx) {
              const Eigen::Vector2d offset((sx + 0.5) / 4 - 0.5, (sy + 0.5) / 4 - 0.5);
              const Eigen::Vector2d ns = *n + j * offset;
              sum += Shade(
                  CastRay(origin, corner_from_camera * ns.homogeneous(), scene, scene.clutter),
                  scene);
            }
          }
          sum /= 16;
        }
      }
      out.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(sum + noise.at<float>(v, u));
    }
  }
  return out;
}

}  // namespace monocle
