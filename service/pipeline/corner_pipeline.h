// The corner pipeline, once for monocled, `monocle corner locate` and `monocle replay`: a
// calibration, the camera's mount, the robot's level and a room map in; a frame in; the
// located corner pose (and, with a map, where the robot stands in it) out. It decides when the
// edge tracker starts afresh, so every caller gives the same poses for the same frames.
#pragma once

#include <memory>
#include <optional>

#include <opencv2/core.hpp>

#include "service/common/result.h"
#include "service/geometry/map_pose.h"
#include "service/geometry/map_pose_tracker.h"
#include "service/geometry/robot_frames.h"
#include "service/geometry/room_map.h"
#include "service/io/calibration_file.h"
#include "service/vision/corner_locator.h"
#include "service/vision/corner_tracker.h"

namespace monocle {

struct CornerPipelineOptions {
  // Follow the edges from frame to frame (frames in order); false: each frame on its own.
  bool track = true;
  CornerTrackerOptions tracking;
  // Camera to ceiling, metres; overrides the calibration's (a configuration's, or a map's
  // ceiling height less the mount's height).
  std::optional<double> ceiling_distance_m;
  // The camera's optical frame in the robot base frame.
  std::optional<RigidTransform> base_camera;
  // How level the robot stands, 1 sigma, radians. With a mount and no map the pose is combined
  // with it (corner_level.h); a map uses it in its own checks. Unset: no level is applied
  // without a map, and the map's default is used with one.
  std::optional<double> level_sigma_rad;
  // With a mount: poses placed in this map, starting from `initial_pose` if given.
  std::shared_ptr<const RoomMap> room_map;
  std::optional<BasePose2d> initial_pose;
};

struct CornerPipelineResult {
  Result<CornerLocation> corner = MakeError(ErrorCode::kNotFound, "not processed");
  std::optional<MapLocation> map;  // with a room map: where the base stands, or why not
};

class CornerPipeline {
 public:
  explicit CornerPipeline(CornerPipelineOptions options);

  // One frame taken with `calibration` at `capture_time_s` (any clock, seconds; unset: 1/30 s
  // after the last). New intrinsics, ceiling distance or roll limit start the tracker afresh.
  CornerPipelineResult Process(const cv::Mat& grey, const CameraCalibration& calibration,
                               std::optional<double> capture_time_s = std::nullopt);
  // A frame that could not be read: the next one is detected, and the map's prior ages.
  void Missed();

  // The ceiling distance a frame taken with `calibration` is solved at (0: unknown).
  double CeilingDistanceM(const CameraCalibration& calibration) const;
  bool in_map() const { return map_tracker_.has_value(); }

 private:
  void UpdateTracker(const CameraIntrinsics& intrinsics, double ceiling_m,
                     const CornerQualityOptions& quality);
  std::optional<MapLocation> PlaceInMap(const CameraIntrinsics& intrinsics,
                                        const Result<CornerLocation>& corner);

  const CornerPipelineOptions options_;
  std::optional<CornerTracker> tracker_;
  CameraIntrinsics tracker_intrinsics_;
  double tracker_ceiling_m_ = 0;
  CornerQualityOptions tracker_quality_;
  std::optional<MapPoseTracker> map_tracker_;
};

}  // namespace monocle
