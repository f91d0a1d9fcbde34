// A located corner pose combined with the level of the robot it is mounted on
// (service/geometry/mount_level.h), and judged again: a pose the level contradicts (it tips the
// robot further than max_level_error_rad and than its own 1 sigma allows) is left as solved
// and flagged suspect; a pose suspect only for its imprecision is no longer, if the level
// makes it precise.
//
// Why: with the ceiling distance given, what a weakly determined view leaves open is mostly
// its tilt (tests/accuracy/corner_pose_notes.md, "Where the tail's information is missing"). A
// robot on a level floor knows its camera's tilt and swing from the mount, to the floor's level.
#pragma once

#include <numbers>

#include "service/geometry/robot_frames.h"
#include "service/vision/corner_locator.h"

namespace monocle {

struct MountLevelOptions {
  // The robot base stands level to this 1 sigma about each horizontal axis (the floor's
  // slope, the suspension, the mount's own error), radians. 0.3 degrees as the room map's.
  double level_sigma_rad = 0.3 * std::numbers::pi / 180;
  // A pose as solved that tips the base further than this is suspect: the image and the
  // mount disagree (a wrong Y, a wrong mount, or a robot on a ramp) ...
  double max_level_error_rad = 1.0 * std::numbers::pi / 180;
  // ... unless its own 1 sigma and the level's allow that tip: a weakly determined view's
  // tilt may be a degree off, and that view is the one the level helps most. The gate is
  // chi-square with 2 degrees of freedom at 0.999 (3.7 sigma).
  double max_tip_mahalanobis2 = 13.8;
};

// `base_camera`: the camera's mount on the robot base (only its rotation is used).
void ApplyMountLevel(const RigidTransform& base_camera, const MountLevelOptions& options,
                     const CornerQualityOptions& quality, CornerLocation* location);

}  // namespace monocle
