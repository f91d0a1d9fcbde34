// What the intrinsics' own uncertainty adds to a corner pose's: the pose is fitted to edge
// points whose rays depend on the intrinsics, so an error in them moves the pose even where
// the edges are measured perfectly. Pure geometry: Eigen only.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"

namespace monocle {

// The measured edges of the X, Y and Z axes as pixels (any points along each edge's seen
// extent), with the number of points each edge's fit had (its weight in the pose fit).
struct CornerEdgePixels {
  std::array<std::vector<Eigen::Vector2d>, 3> points_px;
  std::array<int, 3> fitted_points{};
};

// d(x, y, pan, tilt, swing) / d(fx fy cx cy k1 k2 p1 p2 k3) of the corner pose `pose` fitted to
// these edges with intrinsics `k`, by central differences of the pose fit over steps of
// `step` (one per parameter; a zero step leaves its column zero). Metres and radians per
// parameter unit.
Eigen::Matrix<double, 5, kNumIntrinsicParams> CornerPoseJacobianWrtIntrinsics(
    const CameraIntrinsics& k, const CornerPose& pose, const CornerEdgePixels& edges,
    const IntrinsicParams& step);

// J C J^T for the intrinsics' covariance C (steps of one sigma each): the 5x5 covariance of
// (x, y, pan, tilt, swing) the intrinsics add. Zero when C is.
Eigen::Matrix<double, 5, 5> CornerPoseCovarianceFromIntrinsics(const CameraIntrinsics& k,
                                                               const CornerPose& pose,
                                                               const CornerEdgePixels& edges,
                                                               const IntrinsicsCovariance& c);

}  // namespace monocle
