#include "service/geometry/map_pose_tracker.h"

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
}

std::optional<MapPosePrior> MapPoseTracker::NextPrior() const {
  if (!last_) return std::nullopt;
  return MapPosePrior{
      *last_, options_.gate_distance_m + options_.widen_distance_m_per_frame * frames_since_pose_,
      options_.gate_heading_rad + options_.widen_heading_rad_per_frame * frames_since_pose_};
}

MapLocation MapPoseTracker::Next(const CornerPose& pose,
                                 const Eigen::Matrix<double, 5, 5>& covariance,
                                 const SeenEdgeExtents& seen_extents) {
  MapLocation where = LocateInMap(map_, base_camera_, pose, covariance, NextPrior(), seen_extents);
  if (where.decided()) {
    SetPose(where.consistent.front().base);
  } else {
    ++frames_since_pose_;
  }
  return where;
}

}  // namespace monocle
