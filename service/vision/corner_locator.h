// Camera pose from one image of a ceiling corner: detection (corner_detector), line fits in
// undistorted coordinates, the paper's constrained refit, the closed form of
// service/geometry/corner_pose and its refinement.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>
#include <ostream>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/vision/corner_detector.h"

namespace monocle {

struct CornerLocation {
  CornerPose pose;
  Eigen::Matrix<double, 5, 5> covariance;  // (x, y, pan, tilt, swing)
  // Orientation of the camera in the corner frame: v_corner = q * v_camera, with the camera
  // frame OpenCV's (x right, y down, z forward).
  Eigen::Quaterniond q_corner_camera;
  Eigen::Vector2d corner_px;                   // the corner as the refined pose projects it
  std::array<Eigen::Vector2d, 3> line_end_px;  // far end of the measured X, Y and Z edges
  std::array<int, 3> points_per_line{};        // inlier edge points of X, Y, Z
  double rms_px = 0;                           // RMS distance of edge points to the fitted lines
  CornerEdges edges;                           // what the detector saw (overlays)

  Eigen::Matrix<double, 5, 1> Sigma() const { return covariance.diagonal().cwiseSqrt(); }
};

std::ostream& operator<<(std::ostream& os, const CornerLocation& c);

Result<CornerLocation> LocateCorner(const cv::Mat& grey, const CameraIntrinsics& intrinsics,
                                    double ceiling_distance_m,
                                    const CornerDetectorOptions& options = {});

}  // namespace monocle
