#include "service/pipeline/corner_pipeline.h"

#include <utility>

#include "service/geometry/corner_intrinsics_uncertainty.h"
#include "service/vision/corner_level.h"

namespace monocle {
namespace {

bool SameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
         a.distortion == b.distortion && a.width_px == b.width_px && a.height_px == b.height_px;
}

// corner { max_swing } of the calibration file, else the locator's default.
CornerQualityOptions QualityOf(const CameraCalibration& calibration) {
  CornerQualityOptions quality;
  quality.max_swing_rad = calibration.corner_max_swing_rad.value_or(quality.max_swing_rad);
  return quality;
}

// Edges measured perfectly still give a pose only as certain as the intrinsics they are seen
// through: the calibration's covariance, carried to the pose, is added to the edges'.
void AddIntrinsicsUncertainty(const CameraCalibration& calibration, CornerLocation* corner) {
  if (calibration.intrinsics_covariance.isZero()) return;
  CornerEdgePixels edges;
  for (int axis = 0; axis < 3; ++axis) {
    edges.points_px[axis] = corner->edges.points_px[axis];
    edges.fitted_points[axis] = corner->points_per_line[axis];
  }
  corner->covariance += CornerPoseCovarianceFromIntrinsics(
      calibration.intrinsics, corner->pose, edges, calibration.intrinsics_covariance);
  corner->sigma_includes_intrinsics = true;
}

}  // namespace

CornerPipeline::CornerPipeline(CornerPipelineOptions options) : options_(std::move(options)) {
  if (options_.room_map && options_.base_camera) {
    MapTrackerOptions map_options;
    if (options_.level_sigma_rad) map_options.checks.level_sigma_rad = *options_.level_sigma_rad;
    map_tracker_.emplace(*options_.room_map, *options_.base_camera, map_options);
    if (options_.initial_pose) map_tracker_->SetPose(*options_.initial_pose);
  }
}

double CornerPipeline::CeilingDistanceM(const CameraCalibration& calibration) const {
  return options_.ceiling_distance_m.value_or(calibration.ceiling_distance_m.value_or(0));
}

void CornerPipeline::UpdateTracker(const CameraIntrinsics& intrinsics, double ceiling_m,
                                   const CornerQualityOptions& quality) {
  if (tracker_ && SameIntrinsics(tracker_intrinsics_, intrinsics) &&
      tracker_ceiling_m_ == ceiling_m && tracker_quality_.max_swing_rad == quality.max_swing_rad)
    return;
  tracker_.emplace(intrinsics, ceiling_m, options_.tracking, CornerDetectorOptions{}, quality);
  tracker_intrinsics_ = intrinsics;
  tracker_ceiling_m_ = ceiling_m;
  tracker_quality_ = quality;
}

CornerPipelineResult CornerPipeline::Process(const cv::Mat& grey,
                                             const CameraCalibration& calibration,
                                             std::optional<double> capture_time_s) {
  const CameraIntrinsics& intrinsics = calibration.intrinsics;
  const double ceiling_m = CeilingDistanceM(calibration);
  const CornerQualityOptions quality = QualityOf(calibration);
  CornerPipelineResult out;
  // The tracker needs a scale to predict the next frame's edges; without one every frame is
  // located on its own (and fails for want of a ceiling distance).
  if (options_.track && ceiling_m > 0) {
    UpdateTracker(intrinsics, ceiling_m, quality);
    out.corner = tracker_->Process(grey, capture_time_s);
  } else {
    out.corner = LocateCorner(grey, intrinsics, ceiling_m, {}, quality);
  }
  if (out.corner) AddIntrinsicsUncertainty(calibration, &*out.corner);
  // Without a map, the mount's level when asked for (the map combines the level itself).
  if (out.corner && !map_tracker_ && options_.base_camera && options_.level_sigma_rad) {
    MountLevelOptions level;
    level.level_sigma_rad = *options_.level_sigma_rad;
    ApplyMountLevel(*options_.base_camera, level, quality, &*out.corner);
  }
  if (out.corner && options_.base_camera) {
    out.corner->base =
        BaseInCornerFrame(out.corner->pose, out.corner->covariance, *options_.base_camera);
  }
  out.map = PlaceInMap(intrinsics, out.corner);
  return out;
}

std::optional<MapLocation> CornerPipeline::PlaceInMap(const CameraIntrinsics& intrinsics,
                                                      const Result<CornerLocation>& corner) {
  if (!map_tracker_) return std::nullopt;
  // Frames that are not a sequence are each judged by the room and the initial pose alone.
  if (!options_.track) {
    map_tracker_->Forget();
    if (options_.initial_pose) map_tracker_->SetPose(*options_.initial_pose);
  }
  if (!corner) {
    map_tracker_->Missed();
    return std::nullopt;
  }
  return map_tracker_->Next(
      corner->pose, corner->covariance,
      SeenEdgeExtentsAtLeast(intrinsics, corner->pose, corner->corner_px, corner->line_end_px));
}

void CornerPipeline::Missed() {
  if (tracker_) tracker_->Reset();
  if (!map_tracker_) return;
  if (!options_.track) {
    map_tracker_->Forget();
    if (options_.initial_pose) map_tracker_->SetPose(*options_.initial_pose);
  }
  map_tracker_->Missed();
}

}  // namespace monocle
