// The floor seen from above (`monocle floor map`): where the calibrated floor camera sees the
// floor (its footprint), distance rings around the robot, and the 1-sigma of a floor point
// there as colour with contour lines. The section 4 error analysis of Xu et al. 2017 as a
// picture: each cell's 1 sigma is what `monocle floor measure` reports for the pixel that
// sees it (the same code: AnswerPointRequest, calibration covariance, intrinsics covariance
// and pixel noise).
#pragma once

#include <opencv2/core.hpp>

#include "service/common/result.h"
#include "service/io/calibration_file.h"

namespace monocle::cli {

struct FloorMapOptions {
  double range_m = 6.0;         // shown ahead (Y_w) and to each side (X_w), metres
  double metres_per_px = 0.01;  // map scale
  double cell_m = 0.02;         // the 1 sigma is computed on a grid of this pitch
  double pixel_sigma_px = 0.5;  // pixel noise, as floor measure's default
};

struct FloorMap {
  cv::Mat picture;  // BGR
  // Horizontal 1 sigma, sqrt(sigma_x^2 + sigma_y^2), metres, per map pixel (CV_64F); NaN
  // where the camera does not see the floor.
  cv::Mat sigma_m;
  // Map pixel of the robot frame's origin (below the optical centre); X_w to the right,
  // Y_w (forward) up.
  cv::Point2d origin_px;
  double metres_per_px = 0;
};

// Errors: the calibration has no floor (calibrate it first), or the options are out of range.
Result<FloorMap> RenderFloorMap(const CameraCalibration& calibration,
                                const FloorMapOptions& options);

}  // namespace monocle::cli
