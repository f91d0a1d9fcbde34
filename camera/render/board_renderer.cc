#include "camera/render/board_renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <random>

#include "camera/render/reference_camera.h"

namespace monocle {
namespace {

// Integral of the unit square wave g(x) = +1 on [0, s), -1 on [s, 2s), period 2s.
double TriangleWave(double x, double s) {
  const double period = 2 * s;
  double m = std::fmod(x, period);
  if (m < 0) m += period;
  return m < s ? m : period - m;
}

// Mean of the square wave over [x - w, x + w].
double FilteredSquareWave(double x, double w, double s) {
  if (w < 1e-12) return TriangleWave(x + 1e-12, s) > TriangleWave(x, s) ? 1.0 : -1.0;
  return (TriangleWave(x + w, s) - TriangleWave(x - w, s)) / (2 * w);
}

// Fraction of [x - w, x + w] inside [lo, hi].
double Coverage(double x, double w, double lo, double hi) {
  if (w < 1e-12) return (x >= lo && x < hi) ? 1.0 : 0.0;
  const double overlap = std::min(x + w, hi) - std::max(x - w, lo);
  return std::clamp(overlap / (2 * w), 0.0, 1.0);
}

// Central difference of a coordinate map at (u, v) along one image axis; 0 where undefined.
double MapSlope(const cv::Mat& map, int u, int v, int du, int dv) {
  const int u0 = std::max(u - du, 0), u1 = std::min(u + du, map.cols - 1);
  const int v0 = std::max(v - dv, 0), v1 = std::min(v + dv, map.rows - 1);
  const double a = map.at<double>(v0, u0), b = map.at<double>(v1, u1);
  const double span = du ? u1 - u0 : v1 - v0;
  if (std::isnan(a) || std::isnan(b) || span == 0) return 0.0;
  return (b - a) / span;
}

// The board's outline including its white margin, board frame.
std::vector<Eigen::Vector3d> OuterOutline(const CheckerPattern& p) {
  const double s = p.square_m;
  const double x0 = -2 * s, x1 = (p.cols + 1) * s, y0 = -2 * s, y1 = (p.rows + 1) * s;
  return {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
}

}  // namespace

double CheckerValue(const CheckerPattern& pattern, double x, double y, double wx, double wy,
                    double surround) {
  const double s = pattern.square_m;
  // Checker squares from -s to cols*s; a white margin of one square around them.
  const double in_lo_x = -s, in_hi_x = pattern.cols * s;
  const double in_lo_y = -s, in_hi_y = pattern.rows * s;
  const double checker = FilteredSquareWave(x, wx, s) * FilteredSquareWave(y, wy, s);
  const double checker_value =
      0.5 * (pattern.white + pattern.black) + 0.5 * (pattern.white - pattern.black) * checker;
  const double inner = Coverage(x, wx, in_lo_x, in_hi_x) * Coverage(y, wy, in_lo_y, in_hi_y);
  const double outer =
      Coverage(x, wx, in_lo_x - s, in_hi_x + s) * Coverage(y, wy, in_lo_y - s, in_hi_y + s);
  const double board_value = inner * checker_value + (1 - inner) * pattern.white;
  return outer * board_value + (1 - outer) * surround;
}

BoardLook RandomBoardLook(uint64_t seed, const CameraIntrinsics& k, CheckerPattern* pattern) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 29);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  pattern->white = uniform(170, 235);
  pattern->black = std::max(10.0, pattern->white - uniform(120, 200));
  BoardLook look;
  look.background = uniform(60, 180);
  const double half_diagonal = 0.5 * std::hypot(k.width_px, k.height_px);
  const double angle = uniform(0, 2 * std::numbers::pi);
  look.light_gradient_per_px =
      uniform(0, 0.25) / half_diagonal * Eigen::Vector2d(std::cos(angle), std::sin(angle));
  auto& e = look.effects;
  e.vignetting = uniform(0.0, 0.3);
  e.hotspot_px = Eigen::Vector2d(uniform(0, k.width_px), uniform(0, k.height_px));
  e.hotspot_radius_px = uniform(0.2, 0.5) * k.width_px;
  e.hotspot_gain = uniform(0.0, 0.15);
  e.blur_sigma_px = uniform(0.5, 1.2);
  e.noise_sigma = uniform(1, 3);
  e.jpeg_quality = static_cast<int>(std::lround(uniform(80, 95)));
  return look;
}

cv::Mat RenderBoardView(const CameraIntrinsics& k, const BoardViewPose& pose,
                        const CheckerPattern& pattern, const BoardLook& look, uint64_t seed) {
  const int w = k.width_px, h = k.height_px;
  const Eigen::Matrix3d& r = pose.r_camera_board;
  const Eigen::Vector3d& t = pose.t_camera_board_m;
  const Eigen::Vector3d normal = r.col(2);
  const double plane_offset = normal.dot(t);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const cv::Mat rays = reference::UndistortedPixelGrid(k);
  cv::Mat board_x(h, w, CV_64F), board_y(h, w, CV_64F);
  for (int v = 0; v < h; ++v) {
    const auto* ray = rays.ptr<cv::Point2d>(v);
    auto* bx = board_x.ptr<double>(v);
    auto* by = board_y.ptr<double>(v);
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d dir(ray[u].x, ray[u].y, 1.0);
      const double denom = normal.dot(dir);
      const double depth = std::abs(denom) > 1e-12 ? plane_offset / denom : -1;
      if (!(depth > 0)) {
        bx[u] = by[u] = nan;
        continue;
      }
      const Eigen::Vector3d p_board = r.transpose() * (depth * dir - t);
      bx[u] = p_board.x();
      by[u] = p_board.y();
    }
  }
  cv::Mat radiance(h, w, CV_32F);
  const Eigen::Vector2d centre(0.5 * (w - 1), 0.5 * (h - 1));
  for (int v = 0; v < h; ++v) {
    const auto* bx = board_x.ptr<double>(v);
    const auto* by = board_y.ptr<double>(v);
    auto* out = radiance.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      double value = look.background;
      if (!std::isnan(bx[u])) {
        // Footprint half-widths on the board from the neighbouring pixels.
        const double wx = 0.5 * (std::abs(MapSlope(board_x, u, v, 1, 0)) +
                                 std::abs(MapSlope(board_x, u, v, 0, 1)));
        const double wy = 0.5 * (std::abs(MapSlope(board_y, u, v, 1, 0)) +
                                 std::abs(MapSlope(board_y, u, v, 0, 1)));
        value = CheckerValue(pattern, bx[u], by[u], wx, wy, look.background);
      }
      const double light = 1 + look.light_gradient_per_px.dot(Eigen::Vector2d(u, v) - centre);
      out[u] = static_cast<float>(value * light);
    }
  }
  return Photograph(radiance, look.effects, seed);
}

std::vector<Eigen::Vector2d> ProjectBoardCorners(const CameraIntrinsics& k,
                                                 const BoardViewPose& pose,
                                                 const CheckerPattern& pattern) {
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < pattern.rows; ++j)
    for (int i = 0; i < pattern.cols; ++i)
      points.emplace_back(i * pattern.square_m, j * pattern.square_m, 0);
  std::vector<Eigen::Vector2d> out;
  for (const auto& p :
       reference::ProjectPoints(k, pose.r_camera_board, pose.t_camera_board_m, points))
    out.emplace_back(p.x, p.y);
  return out;
}

std::vector<BoardViewPose> RandomBoardViews(const CameraIntrinsics& k,
                                            const CheckerPattern& pattern, int count, uint64_t seed,
                                            ViewSpread spread) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 31);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const double s = pattern.square_m;
  const Eigen::Vector3d board_centre((pattern.cols - 1) * s / 2, (pattern.rows - 1) * s / 2, 0);
  const double board_width_m = (pattern.cols + 3) * s;
  const auto outline = OuterOutline(pattern);
  std::vector<BoardViewPose> views;
  for (int attempt = 0; attempt < 200 * count && static_cast<int>(views.size()) < count;
       ++attempt) {
    double tilt_deg, fraction;
    Eigen::Vector2d target;  // where the board's centre appears, fraction of the image
    switch (spread) {
      case ViewSpread::kFrontoParallel:
        tilt_deg = uniform(0, 3);
        fraction = uniform(0.35, 0.6);
        target = {uniform(0.25, 0.75), uniform(0.25, 0.75)};
        break;
      case ViewSpread::kOneCorner:
        tilt_deg = uniform(15, 50);
        fraction = uniform(0.2, 0.3);
        target = {uniform(0.12, 0.35), uniform(0.12, 0.35)};
        break;
      default: {
        // As a careful user does: the board in turn near every corner and edge of the image
        // and in its middle (a 3 x 3 grid of places, jittered).
        tilt_deg = uniform(15, 40);
        fraction = uniform(0.3, 0.5);
        const int place = static_cast<int>(views.size()) % 9;
        target = {0.2 + 0.3 * (place % 3) + uniform(-0.08, 0.08),
                  0.2 + 0.3 * (place / 3) + uniform(-0.08, 0.08)};
      }
    }
    const double axis_angle = uniform(0, 2 * std::numbers::pi);
    const Eigen::Vector3d axis(std::cos(axis_angle), std::sin(axis_angle), 0);
    BoardViewPose pose;
    pose.r_camera_board = (Eigen::AngleAxisd(tilt_deg * std::numbers::pi / 180, axis) *
                           Eigen::AngleAxisd(uniform(-0.5, 0.5), Eigen::Vector3d::UnitZ()))
                              .toRotationMatrix();
    const double depth_m = k.fx * board_width_m / (fraction * k.width_px);
    const auto ray = reference::UndistortPixels(
        k, {cv::Point2d(target.x() * k.width_px, target.y() * k.height_px)})[0];
    pose.t_camera_board_m =
        depth_m * Eigen::Vector3d(ray.x, ray.y, 1) - pose.r_camera_board * board_centre;
    // The whole board, margin included, in front of the camera and 3 px inside the image.
    bool inside = true;
    for (const auto& corner : outline) {
      const Eigen::Vector3d p_c = pose.r_camera_board * corner + pose.t_camera_board_m;
      if (p_c.z() <= 0.05) inside = false;
    }
    if (!inside) continue;
    for (const auto& px :
         reference::ProjectPoints(k, pose.r_camera_board, pose.t_camera_board_m, outline)) {
      if (px.x < 3 || px.y < 3 || px.x > k.width_px - 4 || px.y > k.height_px - 4) inside = false;
    }
    if (inside) views.push_back(pose);
  }
  return views;
}

}  // namespace monocle
