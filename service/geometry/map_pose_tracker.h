// Follows the robot through the map frame by frame: each frame's corner pose is placed in the
// map (service/geometry/map_pose.h) with the last decided pose as its prior, so a corner the
// room alone cannot tell apart from the others is decided by where the robot just was.
// Pure geometry: Eigen only, no I/O. Used by `monocle corner locate --map`, monocled and the
// room accuracy test alike.
#pragma once

#include <optional>

#include "service/geometry/map_pose.h"

namespace monocle {

struct MapTrackerOptions {
  // How far the base may move and turn between two consecutive frames with a pose.
  double gate_distance_m = 0.5;
  double gate_heading_rad = 0.5;
  // Each frame without a decided pose widens the gates by what the robot can move in a frame
  // more (a fixed gate after a gap lets a stale prior pick a wrong corner, or none).
  double widen_distance_m_per_frame = 0.1;
  double widen_heading_rad_per_frame = 0.1;
  // Gates wider than this say nothing the room does not: the last pose is dropped and the
  // room alone decides again (one candidate) or reports the view ambiguous. Without the cap
  // a wrong or stale prior (a wrong initial pose) would, once wide enough to hold one
  // look-alike corner but not the true one, pick that one.
  double max_gate_distance_m = 1.5;
  double max_gate_heading_rad = 1.2;
  // When the prior is wrong (the robot was carried, frames were lost, a looped recording
  // starts over), the room alone can still decide: this many consecutive frames with one
  // candidate each, each within the gates of the one before, and that candidate becomes the
  // prior again (the frames themselves stay undecided: reported, not published).
  int frames_to_relocate = 3;
  // The mount's level and the other checks of each placed pose.
  MapCheckOptions checks;
};

class MapPoseTracker {
 public:
  MapPoseTracker(RoomMap map, RigidTransform base_camera, MapTrackerOptions options = {});

  // Where the robot is now (a user's or a request's initial pose); replaces the last pose.
  void SetPose(const BasePose2d& base);
  // Forget the last pose: the next frame is placed by the room alone.
  void Forget();

  // One frame with a corner pose solved at any ceiling distance (pose.z_m), covariance of
  // (x, y, pan, tilt, swing). A decided location becomes the next frame's prior.
  MapLocation Next(const CornerPose& pose, const Eigen::Matrix<double, 5, 5>& covariance,
                   const SeenEdgeExtents& seen_extents);
  // One frame without a corner pose.
  void Missed() { ++frames_since_pose_; }

  // The prior the next frame will be judged against, if any (none once the gates would be
  // wider than the caps).
  std::optional<MapPosePrior> NextPrior() const;
  const RoomMap& map() const { return map_; }
  const RigidTransform& base_camera() const { return base_camera_; }

 private:
  RoomMap map_;
  RigidTransform base_camera_;
  MapTrackerOptions options_;
  std::optional<BasePose2d> last_;
  int frames_since_pose_ = 0;  // frames since `last_`, not counting the next one
  // Consecutive frames the room alone placed at one candidate against the prior: the last.
  std::optional<BasePose2d> relocating_;
  int relocating_frames_ = 0;
};

}  // namespace monocle
