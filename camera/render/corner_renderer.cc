#include "camera/render/corner_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "camera/render/photograph.h"
#include "camera/render/reference_camera.h"
#include "camera/render/supersampled_view.h"

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

// A realistic surface: its paint times a shading gradient across it.
double ShadeRealistic(const Hit& hit, const RealisticLook& look) {
  double base = 0;
  Eigen::Vector2d in_plane = Eigen::Vector2d::Zero();
  const Eigen::Vector2d* gradient = nullptr;
  switch (hit.material) {
    case kCeiling:
      base = look.ceiling_grey;
      in_plane = {hit.point.x(), hit.point.y()};
      gradient = &look.shading_per_m[0];
      break;
    case kWallX0:
      base = look.wall_x0_grey;
      in_plane = {hit.point.y(), hit.point.z()};
      gradient = &look.shading_per_m[1];
      break;
    case kWallY0:
      base = look.wall_y0_grey;
      in_plane = {hit.point.x(), hit.point.z()};
      gradient = &look.shading_per_m[2];
      break;
    case kFloor:
      return 0.6 * look.ceiling_grey;
    case kFarWall:
      return 0.5 * (look.wall_x0_grey + look.wall_y0_grey);
    default:
      return look.ceiling_grey;  // clutter is not drawn in the realistic look
  }
  return base * std::clamp(1 + gradient->dot(in_plane), 0.5, 1.5);
}

double Shade(const Hit& hit, const CornerScene& scene) {
  if (scene.realistic) return ShadeRealistic(hit, *scene.realistic);
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

cv::Mat RenderRadiance(const CameraIntrinsics& k, const CornerPose& pose,
                       const CornerScene& scene) {
  const Eigen::Matrix3d corner_from_camera = reference::RotationCameraFromCorner(pose).transpose();
  const Eigen::Vector3d origin(pose.x_m, pose.y_m, pose.z_m);
  const bool clutter = scene.clutter && !scene.realistic;
  return RenderSupersampledView(k, [&](const cv::Point2d& n, int32_t* material) {
    const Hit hit =
        CastRay(origin, corner_from_camera * Eigen::Vector3d(n.x, n.y, 1), scene, clutter);
    *material = hit.material;
    return Shade(hit, scene);
  });
}

PhotoEffects Effects(const RealisticLook& l) {
  return PhotoEffects{l.vignetting,    l.hotspot_px,  l.hotspot_radius_px, l.hotspot_gain,
                      l.blur_sigma_px, l.noise_sigma, l.jpeg_quality};
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const RealisticLook& l) {
  return os << "RealisticLook{ceiling " << l.ceiling_grey << " walls " << l.wall_x0_grey << " "
            << l.wall_y0_grey << " grey, vignetting " << l.vignetting << ", hot-spot "
            << l.hotspot_gain << " at (" << l.hotspot_px.transpose() << ") r "
            << l.hotspot_radius_px << " px, blur " << l.blur_sigma_px << " px, noise "
            << l.noise_sigma << ", jpeg " << l.jpeg_quality << "}";
}

RealisticLook RandomRealisticLook(uint64_t seed, const CameraIntrinsics& k) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 17);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  RealisticLook l;
  l.ceiling_grey = uniform(150, 215);
  // Walls mostly darker than the ceiling (lit from below, the ceiling faces the lamps less
  // often than the walls do; both happen).
  const double sign = uniform(0, 1) < 0.75 ? -1 : 1;
  const double d1 = uniform(10, 40);
  double d2 = uniform(10, 40);
  while (std::abs(d1 - d2) < 8) d2 = uniform(10, 40);
  l.wall_x0_grey = l.ceiling_grey + sign * d1;
  l.wall_y0_grey = l.ceiling_grey + sign * d2;
  for (auto& g : l.shading_per_m) g = Eigen::Vector2d(uniform(-0.06, 0.06), uniform(-0.06, 0.06));
  l.vignetting = uniform(0.1, 0.3);
  l.hotspot_px = Eigen::Vector2d(uniform(0, k.width_px), uniform(0, k.height_px));
  l.hotspot_radius_px = uniform(0.2, 0.5) * k.width_px;
  l.hotspot_gain = uniform(0.05, 0.25);
  l.blur_sigma_px = uniform(0.7, 1.6);
  l.noise_sigma = uniform(2, 4);
  l.jpeg_quality = static_cast<int>(std::lround(uniform(70, 90)));
  return l;
}

namespace {

// The light over the exposure: one pose, or the average over the motion's samples.
cv::Mat RenderExposedRadiance(const CameraIntrinsics& k, const CornerPose& pose,
                              const CornerScene& scene) {
  if (!scene.exposure_end_pose || scene.motion_samples < 2) return RenderRadiance(k, pose, scene);
  const CornerPose& end = *scene.exposure_end_pose;
  cv::Mat sum;
  for (int i = 0; i < scene.motion_samples; ++i) {
    const double f = static_cast<double>(i) / (scene.motion_samples - 1);
    auto mix = [f](double a, double b) { return a + f * (b - a); };
    const CornerPose at{mix(pose.x_m, end.x_m),           mix(pose.y_m, end.y_m),
                        mix(pose.z_m, end.z_m),           mix(pose.pan_rad, end.pan_rad),
                        mix(pose.tilt_rad, end.tilt_rad), mix(pose.swing_rad, end.swing_rad)};
    const cv::Mat radiance = RenderRadiance(k, at, scene);
    if (sum.empty())
      sum = radiance.clone();
    else
      sum += radiance;
  }
  return sum / scene.motion_samples;
}

}  // namespace

cv::Mat RenderCornerScene(const CameraIntrinsics& k, const CornerPose& pose,
                          const CornerScene& scene) {
  const int w = k.width_px, h = k.height_px;
  cv::Mat value = RenderExposedRadiance(k, pose, scene);
  if (scene.realistic) return Photograph(value, Effects(*scene.realistic), scene.seed);
  if (scene.noise_sigma > 0) {
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(scene.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, scene.noise_sigma);
    value += noise;
  }
  cv::Mat out;
  value.convertTo(out, CV_8U);
  return out;
}

cv::Mat RenderCornerExposure(const CameraIntrinsics& k, const CornerPose& pose,
                             const CornerScene& scene) {
  if (!scene.realistic)
    throw std::invalid_argument("RenderCornerExposure needs the realistic look");
  return Expose(RenderExposedRadiance(k, pose, scene), Effects(*scene.realistic));
}

}  // namespace monocle
