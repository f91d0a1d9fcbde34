// The renderers' own camera: pixel rays and rotations written independently of the
// measurement code, so a convention bug in service/geometry (pixel centre, distortion
// inverse, the paper's rotation order, roll sign) cannot cancel out in render-based tests.
//
// - Pixel -> ray through OpenCV's cv::undistortPoints (iterated to convergence), not our
//   Newton inverse in camera_model.cc.
// - Corner frame -> camera: the paper's eq. (1) multiplied out as printed, as 4x4 row-vector
//   matrices T(Xc, Yc, Zc) R_z(psi) R_x(Theta) F_z, then the swing of section 2.2 as printed
//   ((u_p, v_p) = (u_i, v_i) [cos -sin; sin cos]), not RotationCameraFromCorner.
// - Robot frame -> floor camera: Eigen::AngleAxis rotations about the robot's axes, not
//   RotationCameraFromRobot.
// Pixel centres are at integer coordinates (OpenCV's convention): pixel (0, 0) covers
// [-0.5, 0.5] x [-0.5, 0.5].
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/geometry/floor_model.h"

namespace monocle::reference {

cv::Matx33d CameraMatrix(const CameraIntrinsics& k);
cv::Mat DistortionCoefficients(const CameraIntrinsics& k);  // 1x8, CV_64F

// Normalized (undistorted) coordinates of pixels, by cv::undistortPoints.
std::vector<cv::Point2d> UndistortPixels(const CameraIntrinsics& k,
                                         const std::vector<cv::Point2d>& pixels);

// Normalized coordinates of every pixel centre, CV_64FC2 of height_px x width_px. Shared:
// the last few grids are cached, so never write into the result.
cv::Mat UndistortedPixelGrid(const CameraIntrinsics& k);

// The grids above are cached (21 MB for a 1280 x 1024 lens). While a scope lives they stay;
// when the last one ends the cache is emptied: a service renders its simulated cameras once at
// start-up and must not keep them. (Without any scope the cache keeps the last four.)
class PixelGridCacheScope {
 public:
  PixelGridCacheScope();
  ~PixelGridCacheScope();
  PixelGridCacheScope(const PixelGridCacheScope&) = delete;
  PixelGridCacheScope& operator=(const PixelGridCacheScope&) = delete;
};

// p_camera = R * (p_corner - position), camera frame OpenCV's (x right, y down, z forward).
Eigen::Matrix3d RotationCameraFromCorner(const CornerPose& pose);

// p_camera = R * p_robot + t for the floor camera at (0, 0, height) in the robot frame
// (X_w right, Y_w ahead, Z_w up), pitch about the robot's X axis (90 degrees looks level,
// more looks down), roll about the optical axis (positive turns the image content from +x
// towards +y, clockwise on the screen).
Eigen::Matrix3d RotationCameraFromRobot(const FloorPose& pose);

// Pixels of world points by cv::projectPoints (lens distortion included).
std::vector<cv::Point2d> ProjectPoints(const CameraIntrinsics& k, const Eigen::Matrix3d& r,
                                       const Eigen::Vector3d& t,
                                       const std::vector<Eigen::Vector3d>& points);

}  // namespace monocle::reference
