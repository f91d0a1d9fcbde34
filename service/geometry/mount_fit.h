// The mount's level, fitted: how far a camera's mount on the robot base is tilted and rolled
// from what its CameraMount says, from corner poses taken while the robot stood on a floor
// taken as level. Pure geometry: Eigen only, no I/O.
//
// Why: the mount's level (mount_level.h) helps a pose only as far as the mount's rotation is
// right, and it helps most at a tenth of a degree; a mount measured from a drawing or with a
// ruler is rarely better than half a degree. Each pose of a level robot says where the base's
// up axis points under the given mount. A mount error is fixed in the base frame, so it turns
// with the robot's heading; the floor's slope is fixed in the room and does not. The fit takes
// the mount's correction as what the poses share in the base frame and the rest as the
// floor's tip, drawn afresh for each pose (and the poses' own errors). A floor that slopes the
// same way everywhere tips every pose alike: the views of one corner all face it, so from one
// corner such a slope is partly taken for the mount's; corners on different walls, seen from
// their own frames, turn it in different directions and separate the two.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/corner_pose.h"
#include "service/geometry/robot_frames.h"

namespace monocle {

struct MountFitPose {
  CornerPose pose;
  Eigen::Matrix<double, 5, 5> covariance;  // of (x, y, pan, tilt, swing) as solved
};

struct MountLevelFit {
  RigidTransform mount;  // the given mount, its camera turned by `correction_rad`
  // The camera turned about the base's x axis (ahead) and y axis (left), right-handed,
  // radians: roll and pitch of the mount's error; its covariance, rad^2.
  Eigen::Vector2d correction_rad = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  // How level the robot stood beyond what the poses' own 1 sigma explains (the floor, the
  // suspension), 1 sigma about each horizontal axis, radians: what the level's 1 sigma
  // (level_sigma_deg) should be at least.
  double floor_sigma_rad = 0;
  std::vector<size_t> used;      // indices of the poses the fit rests on
  std::vector<size_t> left_out;  // tipped the base too far from the fit (3.7 sigma): a wrong Y
  std::vector<double> left_out_sigmas;
};

// `mount`: the mount as configured (only its rotation is fitted). Needs at least 5 poses.
Result<MountLevelFit> FitMountLevel(const std::vector<MountFitPose>& poses,
                                    const RigidTransform& mount);

}  // namespace monocle
