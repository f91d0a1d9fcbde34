#include "service/vision/corner_tracker.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

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
  // Steps of 2 % of the distance from the corner, but at least 2 px: the chord between two
  // projected points is straight to far under a pixel either way (2 % steps near the corner
  // were a tenth of a pixel, and half of all steps). Within a few pixels of the corner the image
  // of the axis is straight: one chord to about 4 px off it.
  double t_start = 1e-3 * scale;
  if (const Eigen::Vector3d p = c + t_start * along; p.z() > 1e-3 * scale) {
    const double off_px = (NormalizedToPixel(k, p.head<2>() / p.z()) - corner_px).norm();
    if (off_px > 0 && off_px < 4) t_start *= 4 / off_px;
  }
  for (double t = t_start; t < 100 * scale; t *= 1 + std::max(0.02, 2 / std::max(travelled, 4.0))) {
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

std::array<double, 3> EdgeSigmaPx(const CameraIntrinsics& k, const CornerPrediction& prediction) {
  std::array<double, 3> sigma_px{};
  const CornerPose& pose = prediction.pose;
  // A pose as its rotation and position, computed once: CornerToCamera would recompute the
  // rotation's six sines and cosines for every point projected.
  struct Placed {
    Eigen::Matrix3d camera_from_corner;
    Eigen::Vector3d position_m;
  };
  auto place = [](const CornerPose& p) {
    return Placed{RotationCameraFromCorner(p), CameraPosition(p)};
  };
  const Placed predicted = place(pose);
  // The pose moved by 1 sigma along each of its five parameters (x, y, pan, tilt, swing).
  std::array<Placed, 5> moved;
  for (int i = 0; i < 5; ++i)
    moved[i] = place(MovedBy(pose, prediction.sigma(i) * Eigen::Matrix<double, 5, 1>::Unit(i)));
  const double scale = std::max(CameraPosition(pose).norm(), 0.1);
  auto project = [&k](const Placed& p, const Eigen::Vector3d& corner_point, Eigen::Vector2d* px) {
    const Eigen::Vector3d c = p.camera_from_corner * (corner_point - p.position_m);
    if (c.z() <= 1e-6) return false;
    *px = NormalizedToPixel(k, c.head<2>() / c.z());
    return true;
  };
  for (int axis = 0; axis < 3; ++axis) {
    // Visible points along the axis, 30 % apart, from the corner out to the image border.
    std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero()};
    std::vector<Eigen::Vector2d> pixels(1);
    if (!project(predicted, points[0], &pixels[0])) continue;
    for (double t = 1e-2 * scale; t < 100 * scale; t *= 1.3) {
      const Eigen::Vector3d p = t * Eigen::Vector3d::Unit(axis);
      Eigen::Vector2d px;
      if (!project(predicted, p, &px) || px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 ||
          px.y() > k.height_px - 1)
        break;
      points.push_back(p);
      pixels.push_back(px);
    }
    if (points.size() < 2) continue;
    double worst = 0;
    for (size_t j = 0; j < points.size(); ++j) {
      const size_t a = j == 0 ? 0 : j - 1, b = j == 0 ? 1 : j;
      const Eigen::Vector2d along = (pixels[b] - pixels[a]).normalized();
      const Eigen::Vector2d normal(-along.y(), along.x());
      double variance = 0;
      for (int i = 0; i < 5; ++i) {
        Eigen::Vector2d px;
        const double across = project(moved[i], points[j], &px)
                                  ? normal.dot(px - pixels[j])
                                  : std::numeric_limits<double>::infinity();
        variance += across * across;
      }
      worst = std::max(worst, std::sqrt(variance));
    }
    sigma_px[axis] = worst;
  }
  return sigma_px;
}

std::set<std::string> SuspectReasonKinds(const std::string& reason) {
  std::set<std::string> kinds;
  size_t begin = 0;
  while (begin < reason.size()) {
    size_t end = reason.find("; ", begin);
    if (end == std::string::npos) end = reason.size();
    size_t cut = begin;
    while (cut < end && reason[cut] != ':' &&
           !std::isdigit(static_cast<unsigned char>(reason[cut])))
      ++cut;
    while (cut > begin && reason[cut - 1] == ' ') --cut;
    kinds.insert(reason.substr(begin, cut - begin));
    begin = end + 2;
  }
  return kinds;
}

namespace {

bool IsSubset(const std::set<std::string>& part, const std::set<std::string>& whole) {
  return std::includes(whole.begin(), whole.end(), part.begin(), part.end());
}

// Distance from `p` to the half-line from `origin` along unit `direction`, pixels.
double DistanceToRay(const Eigen::Vector2d& p, const Eigen::Vector2d& origin,
                     const Eigen::Vector2d& direction) {
  const double along = std::max(0.0, (p - origin).dot(direction));
  return (p - origin - along * direction).norm();
}

}  // namespace

CornerTracker::CornerTracker(const CameraIntrinsics& intrinsics, double ceiling_distance_m,
                             const CornerTrackerOptions& options,
                             const CornerDetectorOptions& detector,
                             const CornerQualityOptions& quality)
    : intrinsics_(intrinsics),
      ceiling_distance_m_(ceiling_distance_m),
      options_(options),
      detector_(detector),
      quality_(quality),
      motion_(options.motion) {}

void CornerTracker::Reset() {
  motion_.Reset();
  have_pose_ = false;
  frames_since_detection_ = 0;
  detection_suspect_kinds_.clear();
}

Result<CornerLocation> CornerTracker::Track(const cv::Mat& grey,
                                            const CornerPrediction& prediction) const {
  const CameraIntrinsics& k = intrinsics_;
  if (grey.cols != k.width_px || grey.rows != k.height_px || grey.type() != CV_8UC1)
    return MakeError(ErrorCode::kInvalidArgument, "frame does not match the calibration");
  const CornerPose& predicted = prediction.pose;
  CornerEdges edges;
  edges.noise_sigma_grey = noise_sigma_grey_;
  edges.measurement_noise_grey = measurement_noise_grey_;
  edges.sample_spacing_px = options_.spacing_px;
  const Eigen::Vector3d c = CornerToCamera(predicted, Eigen::Vector3d::Zero());
  if (c.z() <= 0) return MakeError(ErrorCode::kNotFound, "the corner left the view");
  edges.corner_px = NormalizedToPixel(k, c.head<2>() / c.z());
  const double min_step = MinStepGrey(detector_, noise_sigma_grey_);
  std::array<std::vector<Eigen::Vector2d>, 3> predicted_px;
  for (int axis = 0; axis < 3; ++axis) {
    predicted_px[axis] = PredictEdgePx(k, predicted, axis, options_.spacing_px);
    if (predicted_px[axis].size() < 10)
      return MakeError(ErrorCode::kNotFound, "an edge left the view");
    edges.direction[axis] = (predicted_px[axis][1] - predicted_px[axis][0]).normalized();
  }
  const std::array<double, 3> sigma_px = EdgeSigmaPx(k, prediction);
  for (int axis = 0; axis < 3; ++axis) {
    const auto& positions = predicted_px[axis];
    const double gate_px = std::clamp(3 * sigma_px[axis], options_.search_half_width_px,
                                      options_.max_search_half_width_px);
    std::vector<EdgePointSample> samples;
    // Stretches of 8 points, at most kStretches spread along the edge: enough to place the
    // line the locator measures again along its whole length.
    constexpr size_t kStretches = 5;
    const size_t stride = std::max<size_t>(16, (positions.size() + kStretches - 1) / kStretches);
    size_t searched = 0;
    for (size_t begin = 0; begin < positions.size(); begin += stride) {
      const size_t end = std::min(positions.size(), begin + 8);
      // Near the corner the other two edges are close: the search stops short of them.
      double half_width = gate_px;
      for (int other = 0; other < 3; ++other) {
        if (other != axis)
          half_width = std::min(half_width, 0.6 * DistanceToRay(positions[begin], edges.corner_px,
                                                                edges.direction[other]));
      }
      if (half_width < 2) continue;
      searched += end - begin;
      // A 56 px stretch of the lens-bent edge is straight to a fraction of a pixel.
      const Eigen::Vector2d chord = positions[end - 1] - positions[begin];
      const Eigen::Vector2d along = chord.norm() > 0 ? chord.normalized() : edges.direction[axis];
      const int spacing = options_.spacing_px;
      const int count = static_cast<int>(std::lround(chord.norm() / spacing)) + 1;
      const auto chunk = MajoritySign(MeasureEdgeStretch(grey, positions[begin], along, count,
                                                         spacing, half_width, 0, min_step));
      samples.insert(samples.end(), chunk.begin(), chunk.end());
    }
    for (const auto& sample : samples) {
      edges.points_px[axis].push_back(sample.point_px);
      edges.step_grey[axis].push_back(sample.step_grey);
    }
    edges.blur_sigma_px[axis] = EdgeBlurSigmaPx(samples);
    const double coverage = static_cast<double>(edges.points_px[axis].size()) /
                            static_cast<double>(std::max<size_t>(searched, 1));
    if (edges.points_px[axis].size() < 10 || coverage < options_.min_coverage)
      return MakeError(ErrorCode::kNotFound, std::string("edge ") + "XYZ"[axis] +
                                                 " was not found where it was predicted (" +
                                                 std::to_string(edges.points_px[axis].size()) +
                                                 " of " + std::to_string(searched) + " places)");
    int votes = 0;
    for (double s : edges.step_grey[axis]) votes += s > 0 ? 1 : -1;
    edges.polarity[axis] = votes >= 0 ? 1 : -1;
  }
  CornerDetectorOptions measuring = detector_;
  measuring.measure_spacing_px = options_.measure_spacing_px;
  auto located = LocateCornerFromEdges(grey, k, ceiling_distance_m_, std::move(edges), measuring,
                                       quality_, &predicted);
  if (!located) return located;
  located->source = CornerSource::kTracked;
  return located;
}

Result<CornerLocation> CornerTracker::Process(const cv::Mat& grey,
                                              std::optional<double> capture_time_s) {
  time_s_ = capture_time_s ? *capture_time_s : time_s_ + 1.0 / 30;
  const bool detect_now =
      !have_pose_ || frames_since_detection_ + 1 >= options_.detect_every_n_frames;
  fallback_reason_.clear();
  const auto prediction = motion_.Predict(time_s_);
  if (!detect_now && prediction) {
    auto tracked = Track(grey, *prediction);
    // Suspect only for what the detection that started this track was suspect for: the
    // view's own verdict (flagged as such), not a sign the track was lost.
    if (tracked && (!tracked->suspect || IsSubset(SuspectReasonKinds(tracked->suspect_reason),
                                                  detection_suspect_kinds_))) {
      ++frames_since_detection_;
      motion_.Update(tracked->pose, time_s_);
      return tracked;
    }
    fallback_reason_ =
        tracked ? "tracked pose suspect: " + tracked->suspect_reason : tracked.error().message;
  }
  auto detected = LocateCorner(grey, intrinsics_, ceiling_distance_m_, detector_, quality_);
  frames_since_detection_ = 0;
  if (detected) {
    have_pose_ = true;
    motion_.Update(detected->pose, time_s_);
    detection_suspect_kinds_ =
        detected->suspect ? SuspectReasonKinds(detected->suspect_reason) : std::set<std::string>{};
    noise_sigma_grey_ = detected->edges.noise_sigma_grey;
    measurement_noise_grey_ = detected->edges.measurement_noise_grey;
    detected->source = CornerSource::kDetected;
  } else {
    Reset();
  }
  return detected;
}

}  // namespace monocle
