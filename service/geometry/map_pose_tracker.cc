#include "service/geometry/map_pose_tracker.h"

#include <cmath>
#include <utility>

namespace monocle {

MapPoseTracker::MapPoseTracker(RoomMap map, RigidTransform base_camera, MapTrackerOptions options)
    : map_(std::move(map)), base_camera_(std::move(base_camera)), options_(options) {}

void MapPoseTracker::SetPose(const BasePose2d& base) {
  last_ = base;
  frames_since_pose_ = 0;
}

void MapPoseTracker::Forget() {
  last_.reset();
  frames_since_pose_ = 0;
  relocating_.reset();
}

std::optional<MapPosePrior> MapPoseTracker::NextPrior() const {
  if (!last_) return std::nullopt;
  const MapPosePrior prior{
      *last_, options_.gate_distance_m + options_.widen_distance_m_per_frame * frames_since_pose_,
      options_.gate_heading_rad + options_.widen_heading_rad_per_frame * frames_since_pose_};
  if (prior.max_distance_m > options_.max_gate_distance_m + 1e-9 ||
      prior.max_heading_rad > options_.max_gate_heading_rad + 1e-9)
    return std::nullopt;
  return prior;
}

MapLocation MapPoseTracker::Next(const CornerPose& pose,
                                 const Eigen::Matrix<double, 5, 5>& covariance,
                                 const SeenEdgeExtents& seen_extents) {
  const std::optional<MapPosePrior> prior = NextPrior();
  if (!prior) last_.reset();  // lost: the room alone decides
  MapLocation where =
      LocateInMap(map_, base_camera_, pose, covariance, prior, seen_extents, options_.checks);
  if (where.decided()) {
    SetPose(where.consistent.front().base);
    relocating_.reset();
    return where;
  }
  ++frames_since_pose_;
  if (where.prior_contradicted && where.consistent.size() == 1) {
    const BasePose2d& here = where.consistent.front().base;
    const bool follows = relocating_ &&
                         std::hypot(here.x_m - relocating_->x_m, here.y_m - relocating_->y_m) <=
                             options_.gate_distance_m &&
                         std::abs(std::remainder(here.heading_rad - relocating_->heading_rad,
                                                 2 * M_PI)) <= options_.gate_heading_rad;
    relocating_frames_ = follows ? relocating_frames_ + 1 : 1;
    relocating_ = here;
    if (relocating_frames_ >= options_.frames_to_relocate) SetPose(here);
  } else {
    relocating_.reset();
  }
  return where;
}

}  // namespace monocle
