// Floor calibration from one image of a chessboard lying on the floor: detection plus the
// geometry, with the checks a user needs (image size, a pose that can be real). Shared by
// `monocle floor calibrate` and the service's floor calibration command.
#pragma once

#include <opencv2/core.hpp>

#include "service/geometry/floor_calibration.h"
#include "service/vision/chessboard.h"

namespace monocle {

struct FloorCalibrationFromImage {
  FloorCalibration calibration;
  size_t corners = 0;      // board corners used
  BoardObservation board;  // the corners found, for overlays and guidance
};

Result<FloorCalibrationFromImage> CalibrateFloorFromImage(
    const cv::Mat& grey, const CameraIntrinsics& intrinsics, const BoardSpec& board,
    FloorCalibrationMethod method,
    const IntrinsicsCovariance& k_covariance = IntrinsicsCovariance::Zero());

}  // namespace monocle
