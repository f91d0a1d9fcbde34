// Chessboard corner detection with OpenCV, returned in the board frame the floor
// calibration expects (x_p to the right in the image, y_p away from the camera).
#pragma once

#include <opencv2/core.hpp>

#include "service/common/result.h"
#include "service/geometry/floor_calibration.h"

namespace monocle {

struct BoardSpec {
  int cols = 0;  // inner corners per row as the user counts them
  int rows = 0;  // inner corners per column
  double square_m = 0;
};

// Finds the board in an 8-bit grey image, refines corners to subpixel accuracy and orders
// them. If the board appears turned by 90 degrees, cols and rows of the result are swapped
// so that x_p still runs to the right in the image.
Result<BoardObservation> DetectChessboard(const cv::Mat& grey, const BoardSpec& spec);

// Parses "COLSxROWS", e.g. "9x6".
Result<BoardSpec> ParseBoardSize(const std::string& text, double square_m);

}  // namespace monocle
