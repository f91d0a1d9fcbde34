#include "service/vision/corner_tracker.h"

#include <algorithm>
#include <cmath>

namespace monocle {

std::vector<Eigen::Vector2d> PredictEdgePx(const CameraIntrinsics& k, const CornerPose& pose,
                                           int axis, int spacing_px) {
  std::vector<Eigen::Vector2d> positions;
  const double scale = std::max(CameraPosition(pose).norm(), 0.1);
  const Eigen::Vector3d c = CornerToCamera(pose, Eigen::Vector3d::Zero());
  const Eigen::Vector2d corner_px = NormalizedToPixel(k, c.head<2>() / c.z());
  Eigen::Vector2d previous = corner_px;
  double travelled = 0, next = 8;  // first sample 8 px off the corner, where edges separate
  // The axis in the camera frame: c + t * along (the rotation computed once, not per step).
  const Eigen::Vector3d along = RotationCameraFromCorner(pose).col(axis);
  // 2 % steps: the chord between two projected points is straight to far under a pixel.
  for (double t = 1e-3 * scale; t < 100 * scale; t *= 1.02) {
    const Eigen::Vector3d p = c + t * along;
    if (p.z() <= 1e-3 * scale) break;
    const Eigen::Vector2d px = NormalizedToPixel(k, p.head<2>() / p.z());
    if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1) break;
    const double step = (px - previous).norm();
    if (step <= 0) continue;
    while (travelled + step >= next) {  // resample the curve at equal arc length
      positions.push_back(previous + (next - travelled) / step * (px - previous));
      next += spacing_px;
    }
    travelled += step;
    previous = px;
  }
  return positions;
}

CornerTracker::CornerTracker(const CameraIntrinsics& intrinsics, double ceiling_distance_m,
                             const CornerTrackerOptions& options,
                             const CornerDetectorOptions& detector,
                             const CornerQualityOptions& quality)
    : intrinsics_(intrinsics),
      ceiling_distance_m_(ceiling_distance_m),
      options_(options),
      detector_(detector),
      quality_(quality) {}

void CornerTracker::Reset() {
  last_pose_.reset();
  frames_since_detection_ = 0;
}

Result<CornerLocation> CornerTracker::Track(const cv::Mat& grey) const {
  const CameraIntrinsics& k = intrinsics_;
  if (grey.cols != k.width_px || grey.rows != k.height_px || grey.type() != CV_8UC1)
    return MakeError(ErrorCode::kInvalidArgument, "frame does not match the calibration");
  CornerEdges edges;
  edges.noise_sigma_grey = noise_sigma_grey_;
  edges.measurement_noise_grey = measurement_noise_grey_;
  edges.sample_spacing_px = options_.spacing_px;
  const Eigen::Vector3d c = CornerToCamera(*last_pose_, Eigen::Vector3d::Zero());
  if (c.z() <= 0) return MakeError(ErrorCode::kNotFound, "the corner left the view");
  edges.corner_px = NormalizedToPixel(k, c.head<2>() / c.z());
  const double min_step = MinStepGrey(detector_, noise_sigma_grey_);
  for (int axis = 0; axis < 3; ++axis) {
    const auto positions = PredictEdgePx(k, *last_pose_, axis, options_.spacing_px);
    if (positions.size() < 10) return MakeError(ErrorCode::kNotFound, "an edge left the view");
    edges.direction[axis] = (positions[1] - positions[0]).normalized();
    std::vector<EdgePointSample> samples;
    for (size_t begin = 0; begin < positions.size(); begin += 16) {
      const size_t end = std::min(positions.size(), begin + 16);
      // A 48 px stretch of the lens-bent edge is straight to well under 0.1 px.
      const Eigen::Vector2d chord = positions[end - 1] - positions[begin];
      const Eigen::Vector2d along = chord.norm() > 0 ? chord.normalized() : edges.direction[axis];
      const int spacing = options_.spacing_px;
      const int count = static_cast<int>(std::lround(chord.norm() / spacing)) + 1;
      const auto chunk =
          MajoritySign(MeasureEdgeStretch(grey, positions[begin], along, count, spacing,
                                          options_.search_half_width_px, 0, min_step));
      samples.insert(samples.end(), chunk.begin(), chunk.end());
    }
    for (const auto& sample : samples) {
      edges.points_px[axis].push_back(sample.point_px);
      edges.step_grey[axis].push_back(sample.step_grey);
    }
    edges.blur_sigma_px[axis] = EdgeBlurSigmaPx(samples);
    const double coverage =
        static_cast<double>(edges.points_px[axis].size()) / static_cast<double>(positions.size());
    if (edges.points_px[axis].size() < 10 || coverage < options_.min_coverage)
      return MakeError(ErrorCode::kNotFound, std::string("edge ") + "XYZ"[axis] +
                                                 " was not found where it was predicted (" +
                                                 std::to_string(edges.points_px[axis].size()) +
                                                 " of " + std::to_string(positions.size()) +
                                                 " places)");
    int votes = 0;
    for (double s : edges.step_grey[axis]) votes += s > 0 ? 1 : -1;
    edges.polarity[axis] = votes >= 0 ? 1 : -1;
  }
  auto located = LocateCornerFromEdges(grey, k, ceiling_distance_m_, std::move(edges), detector_,
                                       quality_, &*last_pose_);
  if (!located) return located;
  located->source = CornerSource::kTracked;
  return located;
}

Result<CornerLocation> CornerTracker::Process(const cv::Mat& grey) {
  const bool detect_now =
      !last_pose_ || frames_since_detection_ + 1 >= options_.detect_every_n_frames;
  fallback_reason_.clear();
  if (!detect_now) {
    auto tracked = Track(grey);
    if (tracked && !tracked->suspect) {
      ++frames_since_detection_;
      last_pose_ = tracked->pose;
      return tracked;
    }
    fallback_reason_ =
        tracked ? "tracked pose suspect: " + tracked->suspect_reason : tracked.error().message;
  }
  auto detected = LocateCorner(grey, intrinsics_, ceiling_distance_m_, detector_, quality_);
  frames_since_detection_ = 0;
  if (detected) {
    last_pose_ = detected->pose;
    noise_sigma_grey_ = detected->edges.noise_sigma_grey;
    measurement_noise_grey_ = detected->edges.measurement_noise_grey;
    detected->source = CornerSource::kDetected;
  } else {
    last_pose_.reset();
  }
  return detected;
}

}  // namespace monocle
