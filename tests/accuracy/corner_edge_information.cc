#include "tests/accuracy/corner_edge_information.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "camera/render/reference_camera.h"

namespace monocle::testing {
namespace {

constexpr double kMinDepthM = 0.05;  // points nearer the camera plane than this are left out
constexpr double kSpacingPx = 0.25;
constexpr double kParameterStep = 1e-6;  // m and rad, for the central differences

// The pose moved by `step` along parameter `index` (x, y, pan, tilt, swing).
CornerPose Moved(CornerPose pose, int index, double step) {
  double* fields[5] = {&pose.x_m, &pose.y_m, &pose.pan_rad, &pose.tilt_rad, &pose.swing_rad};
  *fields[index] += step;
  return pose;
}

std::vector<Eigen::Vector2d> Project(const CameraIntrinsics& k, const CornerPose& pose,
                                     const std::vector<Eigen::Vector3d>& points_corner) {
  const Eigen::Matrix3d r = reference::RotationCameraFromCorner(pose);
  const Eigen::Vector3d t = -r * Eigen::Vector3d(pose.x_m, pose.y_m, pose.z_m);
  const auto pixels = reference::ProjectPoints(k, r, t, points_corner);
  std::vector<Eigen::Vector2d> out;
  out.reserve(pixels.size());
  for (const auto& p : pixels) out.emplace_back(p.x, p.y);
  return out;
}

// Distances t (m) along `axis` from the corner to `length_m`, spaced about kSpacingPx apart in
// the undistorted image. With the point at t in the camera frame c + t d, s = t / (c_z + t d_z)
// makes the undistorted image point linear in s, so equal steps in s are equal steps there.
// Only the stretch whose undistorted image lies within twice the image's extent about the
// principal point: the rest cannot be in the image (the lenses used here bend a point by a few
// percent, and monotonically), and an edge running towards the camera's plane would otherwise
// be sampled over up to 10^5 px of image beyond the frame: the bounds of 72 realistic views took
// 50 s, 22 s with this (7 s since the reference camera's undistortion stops once converged).
// The bounds agree with before within 0.3 % (the samples fall elsewhere along the edge).
std::vector<double> DistancesAlongEdge(const CameraIntrinsics& k, const CornerPose& pose, int axis,
                                       double length_m) {
  const Eigen::Matrix3d r = reference::RotationCameraFromCorner(pose);
  const Eigen::Vector3d c = -r * Eigen::Vector3d(pose.x_m, pose.y_m, pose.z_m);
  const Eigen::Vector3d d = r.col(axis);
  if (c.z() <= kMinDepthM) return {};
  double end_m = length_m;
  if (c.z() + end_m * d.z() < kMinDepthM) end_m = (kMinDepthM - c.z()) / d.z();
  double s_begin = 0, s_end = end_m / (c.z() + end_m * d.z());
  const Eigen::Vector2d origin = c.head<2>() / c.z();
  const Eigen::Vector2d image_rate = d.head<2>() - d.z() * origin;
  const Eigen::Vector2d half_extent(2 * std::max(k.cx, k.width_px - k.cx) / k.fx,
                                    2 * std::max(k.cy, k.height_px - k.cy) / k.fy);
  for (int i = 0; i < 2; ++i) {
    if (std::abs(image_rate[i]) < 1e-12) {
      if (std::abs(origin[i]) > half_extent[i]) return {};
      continue;
    }
    const double a = (-half_extent[i] - origin[i]) / image_rate[i];
    const double b = (half_extent[i] - origin[i]) / image_rate[i];
    s_begin = std::max(s_begin, std::min(a, b));
    s_end = std::min(s_end, std::max(a, b));
  }
  if (!(s_end > s_begin)) return {};
  const double length_px = k.fx * image_rate.norm() * (s_end - s_begin);
  const int count = std::clamp(static_cast<int>(length_px / kSpacingPx) + 2, 2, 400000);
  std::vector<double> t(count);
  for (int i = 0; i < count; ++i) {
    const double s = s_begin + (s_end - s_begin) * i / (count - 1);
    t[i] = s * c.z() / (1 - s * d.z());
  }
  return t;
}

double Bilinear(const cv::Mat& grey, const Eigen::Vector2d& p) {
  const int u0 = static_cast<int>(std::floor(p.x())), v0 = static_cast<int>(std::floor(p.y()));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= grey.cols || v0 + 1 >= grey.rows) return std::nan("");
  const double a = p.x() - u0, b = p.y() - v0;
  auto at = [&](int v, int u) { return static_cast<double>(grey.at<float>(v, u)); };
  return (1 - b) * ((1 - a) * at(v0, u0) + a * at(v0, u0 + 1)) +
         b * ((1 - a) * at(v0 + 1, u0) + a * at(v0 + 1, u0 + 1));
}

}  // namespace

std::vector<EdgeSample> SampleCornerEdges(const CameraIntrinsics& k, const CornerPose& pose,
                                          const std::array<double, 3>& edge_length_m,
                                          double junction_px) {
  const Eigen::Vector2d corner_px = Project(k, pose, {Eigen::Vector3d::Zero()})[0];
  std::vector<EdgeSample> samples;
  for (int axis = 0; axis < 3; ++axis) {
    const auto t = DistancesAlongEdge(k, pose, axis, edge_length_m[axis]);
    if (t.size() < 2) continue;
    std::vector<Eigen::Vector3d> ends, middles;
    for (double ti : t) ends.push_back(ti * Eigen::Vector3d::Unit(axis));
    for (size_t i = 0; i + 1 < t.size(); ++i)
      middles.push_back(0.5 * (t[i] + t[i + 1]) * Eigen::Vector3d::Unit(axis));
    const auto end_px = Project(k, pose, ends);
    const auto middle_px = Project(k, pose, middles);
    std::array<std::vector<Eigen::Vector2d>, 5> plus, minus;
    for (int j = 0; j < 5; ++j) {
      plus[j] = Project(k, Moved(pose, j, kParameterStep), middles);
      minus[j] = Project(k, Moved(pose, j, -kParameterStep), middles);
    }
    for (size_t i = 0; i < middles.size(); ++i) {
      const Eigen::Vector2d& p = middle_px[i];
      if (p.x() < 0 || p.y() < 0 || p.x() > k.width_px - 1 || p.y() > k.height_px - 1) continue;
      if ((p - corner_px).norm() < junction_px) continue;
      const Eigen::Vector2d along = end_px[i + 1] - end_px[i];
      if (along.norm() <= 0) continue;
      EdgeSample s;
      s.axis = axis;
      s.pixel = p;
      s.length_px = along.norm();
      s.normal = Eigen::Vector2d(-along.y(), along.x()) / along.norm();
      for (int j = 0; j < 5; ++j)
        s.normal_shift_px[j] = s.normal.dot(plus[j][i] - minus[j][i]) / (2 * kParameterStep);
      samples.push_back(s);
    }
  }
  return samples;
}

std::vector<double> EdgeContrastGrey(const std::vector<EdgeSample>& samples,
                                     const cv::Mat& noise_free_grey, double offset_px) {
  cv::Mat grey;
  noise_free_grey.convertTo(grey, CV_32F);
  std::vector<double> contrast;
  contrast.reserve(samples.size());
  for (const auto& s : samples) {
    const double a = Bilinear(grey, s.pixel + offset_px * s.normal);
    const double b = Bilinear(grey, s.pixel - offset_px * s.normal);
    contrast.push_back(std::isnan(a) || std::isnan(b) ? 0.0 : std::abs(a - b));
  }
  return contrast;
}

PoseMatrix CornerEdgeFisherInformation(const std::vector<EdgeSample>& samples,
                                       const std::vector<double>& contrast_grey,
                                       double blur_sigma_px, double noise_sigma_grey) {
  // The pixel's area is a box of width 1 (variance 1/12) after the blur; rounding to 8 bits
  // adds noise of variance 1/12.
  const double blur = std::sqrt(blur_sigma_px * blur_sigma_px + 1.0 / 12);
  const double noise2 = noise_sigma_grey * noise_sigma_grey + 1.0 / 12;
  // Integral over the normal of (C g(d))^2 for a unit-area Gaussian g of sigma `blur`.
  const double per_contrast2 = 1 / (2 * std::sqrt(std::numbers::pi) * blur * noise2);
  PoseMatrix information = PoseMatrix::Zero();
  for (size_t i = 0; i < samples.size(); ++i) {
    const double c = contrast_grey[i];
    information += samples[i].length_px * c * c * per_contrast2 * samples[i].normal_shift_px *
                   samples[i].normal_shift_px.transpose();
  }
  return information;
}

Eigen::Matrix2d HorizontalPositionBound(const PoseMatrix& information) {
  const Eigen::FullPivLU<PoseMatrix> lu(information);
  if (!lu.isInvertible()) return Eigen::Matrix2d::Constant(std::numeric_limits<double>::infinity());
  return lu.inverse().topLeftCorner<2, 2>();
}

}  // namespace monocle::testing
