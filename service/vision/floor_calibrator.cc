#include "service/vision/floor_calibrator.h"

#include <numbers>
#include <sstream>

namespace monocle {

Result<FloorCalibrationFromImage> CalibrateFloorFromImage(
    const cv::Mat& grey, const CameraIntrinsics& k, const BoardSpec& spec,
    FloorCalibrationMethod method, const IntrinsicsCovariance& k_covariance) {
  if (grey.cols != k.width_px || grey.rows != k.height_px) {
    std::ostringstream os;
    os << "image is " << grey.cols << "x" << grey.rows << " but the calibration is for "
       << k.width_px << "x" << k.height_px;
    return MakeError(ErrorCode::kInvalidArgument, os.str());
  }
  const auto board = DetectChessboard(grey, spec);
  if (!board) return board.error();
  auto result = CalibrateFloor(k, *board, method, k_covariance);
  if (!result) return result.error();
  if (!(result->pose.height_m > 0) ||
      !(result->pose.pitch_rad > 0 && result->pose.pitch_rad < std::numbers::pi)) {
    return MakeError(ErrorCode::kDegenerate,
                     "the calibration gave an impossible pose (height <= 0 or pitch outside (0, "
                     "pi)); the board is probably not on the floor in view");
  }
  return FloorCalibrationFromImage{*result, board->pixels.size(), *board};
}

}  // namespace monocle
