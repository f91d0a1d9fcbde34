// The robot's pose in the map frame from a corner pose (Chou & Tsai in whichever corner's
// frame): which corner of the map it is, decided by what is consistent, never guessed.
// Pure geometry: Eigen only, no I/O.
//
// Every map corner is tried. The camera's height above the floor (its mount) gives each
// corner's ceiling distance; the corner pose scales with it exactly (the image of a corner
// fixes the camera's position only up to scale). A candidate is consistent when the camera is
// inside the corner's room and sees the corner with no wall between, and, given a prior (the
// previous pose, or one the user gives), lies within its gates. How far the edges were seen
// along the walls counts too: a wall shorter than the edge seen on it is not that wall. One
// consistent candidate is the answer; several are reported as ambiguous, with all of them.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/geometry/mount_level.h"
#include "service/geometry/robot_frames.h"
#include "service/geometry/room_map.h"

namespace monocle {

// The robot base on the floor: x, y in the map (metres), heading of its x axis (radians from
// the map's +x towards +y).
struct BasePose2d {
  double x_m = 0, y_m = 0, heading_rad = 0;
};
std::ostream& operator<<(std::ostream& os, const BasePose2d& p);

struct MapPosePrior {
  BasePose2d base;
  double max_distance_m = 0.5;   // how far the base may have moved since
  double max_heading_rad = 0.5;  // how far it may have turned
};

struct MapCheckOptions {
  // The robot stands level on the floor to this 1 sigma (floors, ramps, braking), radians: the
  // mount then fixes the camera's tilt and swing, which the corner solve measured freely; the
  // two are combined (a linear Gaussian update of the pose by its covariance) before the pose
  // is placed in the map. Far corners, whose tilt is least certain, gain most.
  double level_sigma_rad = 0.3 * M_PI / 180;
  // Above this the pose is suspect: the image and the mount disagree.
  double max_level_error_rad = 1.0 * M_PI / 180;
};

struct MapPoseCandidate {
  std::string corner_id, room_id;
  CornerPose corner_pose;     // in that corner's frame, at its ceiling distance
  RigidTransform map_camera;  // the optical frame in the map
  BasePose2d base;
  Eigen::Matrix3d base_covariance = Eigen::Matrix3d::Zero();  // x, y, heading: m^2, rad^2
};

struct MapLocation {
  std::vector<MapPoseCandidate> consistent;  // best first (closest to the prior, if any)
  // How far the solved camera orientation tips the robot base from level (the mount fixes the
  // camera's tilt and swing on a level floor; the corner solve does not use that), before the
  // two are combined: the same for every candidate. Above
  // MapCheckOptions::max_level_error_rad the pose is suspect.
  double level_error_rad = 0;
  bool suspect = false;
  std::string suspect_reason;
  bool prior_contradicted = false;  // a prior was given and no candidate met its gates
  std::string why_none;             // when `consistent` is empty
  bool ambiguous() const { return consistent.size() > 1; }
  // One answer that nothing contradicts: the pose to publish. Otherwise report, never guess.
  bool decided() const { return consistent.size() == 1 && !prior_contradicted; }
};

// How far from the corner each edge (X, Y, Z) was seen, in the units of the pose it was
// solved with (pose.z_m), 0 where not known; and the ray through each edge's seen far end
// (direction in the corner frame, zero where not known). An edge seen further than its wall
// runs is still that wall's when the ray meets the next wall's ceiling edge: seen from some
// places the two run on nearly in line in the image and the detector fits both as one.
struct SeenEdgeExtents {
  std::array<double, 3> along{0, 0, 0};
  std::array<Eigen::Vector3d, 3> end_ray_corner{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                Eigen::Vector3d::Zero()};
  double operator[](int axis) const { return along[axis]; }
};

// The distance from the corner, along `axis` (0 X, 1 Y, 2 Z), of the edge point seen at pixel
// `end_px`: where the pixel's ray passes closest to the axis. 0 if the ray runs parallel.
double SeenEdgeExtent(const CameraIntrinsics& intrinsics, const CornerPose& pose, int axis,
                      const Eigen::Vector2d& end_px);

// What the edges' far ends (`end_px`, X Y Z) show for certain: each end taken `margin_px`
// back towards the corner first. An edge seen at a grazing angle (the camera nearly under
// it) runs towards its vanishing point, where a pixel spans metres of the edge.
SeenEdgeExtents SeenEdgeExtentsAtLeast(const CameraIntrinsics& intrinsics, const CornerPose& pose,
                                       const Eigen::Vector2d& corner_px,
                                       const std::array<Eigen::Vector2d, 3>& end_px,
                                       double margin_px = 3);

// `pose` was solved at ceiling distance pose.z_m, with covariance `covariance` of (x, y, pan,
// tilt, swing) (m^2, rad^2). `base_camera`: the mount, its translation's z the optical
// centre's height above the floor.
MapLocation LocateInMap(const RoomMap& map, const RigidTransform& base_camera,
                        const CornerPose& pose, const Eigen::Matrix<double, 5, 5>& covariance,
                        const std::optional<MapPosePrior>& prior,
                        const SeenEdgeExtents& seen_extents = {},
                        const MapCheckOptions& checks = {});

// The same for one given corner (no consistency test): the corner pose scaled to the
// corner's ceiling distance, and the camera and base in the map.
MapPoseCandidate PoseInMapFromCorner(const MapCorner& corner, const RigidTransform& base_camera,
                                     const CornerPose& pose,
                                     const Eigen::Matrix<double, 5, 5>& covariance);

}  // namespace monocle
