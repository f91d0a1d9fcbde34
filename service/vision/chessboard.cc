#include "service/vision/chessboard.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

namespace monocle {

Result<BoardSpec> ParseBoardSize(const std::string& text, double square_m) {
  static const std::regex pattern(R"(^\s*(\d+)\s*[xX]\s*(\d+)\s*$)");
  std::smatch match;
  if (!std::regex_match(text, match, pattern)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--board '" + text + "' is not COLSxROWS (inner corners, e.g. 9x6)");
  }
  BoardSpec spec{std::stoi(match[1]), std::stoi(match[2]), square_m};
  // OpenCV's detector needs at least 3 inner corners each way (it throws on fewer: found by
  // tests/fuzz/requests_fuzz, a remote calibration request for a 2x5 board ended monocled).
  if (spec.cols < 3 || spec.rows < 3 || spec.cols > 100 || spec.rows > 100) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--board '" + text + "': each count of inner corners must be 3..100");
  }
  if (!(square_m > 0) || !std::isfinite(square_m)) {
    return MakeError(ErrorCode::kInvalidArgument, "--square must be a positive length in metres");
  }
  return spec;
}

namespace {

// Where corner (i, j) should be by its neighbours: the median of the midpoints of its two
// neighbours along each axis and of the extrapolations from two neighbours on one side.
// On a board seen in perspective these agree with the true corner to a few tenths of a
// pixel; a corner further off was refined onto the wrong saddle.
cv::Point2f PredictFromNeighbours(const std::vector<cv::Point2f>& c, int cols, int rows, int i,
                                  int j) {
  auto at = [&](int a, int b) { return c[b * cols + a]; };
  std::vector<cv::Point2f> guesses;
  if (i > 0 && i + 1 < cols) guesses.push_back(0.5f * (at(i - 1, j) + at(i + 1, j)));
  if (j > 0 && j + 1 < rows) guesses.push_back(0.5f * (at(i, j - 1) + at(i, j + 1)));
  if (i + 2 < cols) guesses.push_back(2.0f * at(i + 1, j) - at(i + 2, j));
  if (i >= 2) guesses.push_back(2.0f * at(i - 1, j) - at(i - 2, j));
  if (j + 2 < rows) guesses.push_back(2.0f * at(i, j + 1) - at(i, j + 2));
  if (j >= 2) guesses.push_back(2.0f * at(i, j - 1) - at(i, j - 2));
  std::vector<float> xs, ys;
  for (const auto& g : guesses) {
    xs.push_back(g.x);
    ys.push_back(g.y);
  }
  std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
  std::nth_element(ys.begin(), ys.begin() + ys.size() / 2, ys.end());
  return {xs[xs.size() / 2], ys[ys.size() / 2]};
}

}  // namespace

Result<BoardObservation> DetectChessboard(const cv::Mat& grey, const BoardSpec& spec) {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return MakeError(ErrorCode::kInvalidArgument, "board detection needs an 8-bit grey image");
  }
  if (spec.cols < 3 || spec.rows < 3) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "a chessboard needs at least 3x3 inner corners, not " +
                         std::to_string(spec.cols) + "x" + std::to_string(spec.rows));
  }
  // OpenCV's sector-based detector, coarse to fine. The classic findChessboardCorners can
  // take minutes when a larger board than requested is in view (measured: 157 s for 10x8
  // on an 11x8 board at 1280x1024); SB fails in a fraction of a second instead. Detecting on
  // a reduced image is 3-5x faster; the corners are refined at full resolution below.
  std::vector<cv::Point2f> corners;
  bool found = false;
  for (const double scale : {0.35, 0.5, 1.0}) {
    if (scale < 1.0 && std::min(grey.cols, grey.rows) * scale < 240) continue;
    cv::Mat scaled = grey;
    if (scale < 1.0) cv::resize(grey, scaled, cv::Size(), scale, scale, cv::INTER_AREA);
    if (cv::findChessboardCornersSB(scaled, cv::Size(spec.cols, spec.rows), corners, 0)) {
      // INTER_AREA maps pixel centres as (x + 0.5) * scale - 0.5.
      for (auto& c : corners)
        c = (c + cv::Point2f(0.5f, 0.5f)) * static_cast<float>(1.0 / scale) -
            cv::Point2f(0.5f, 0.5f);
      found = true;
      break;
    }
  }
  if (!found) {
    return MakeError(ErrorCode::kNotFound,
                     "no " + std::to_string(spec.cols) + "x" + std::to_string(spec.rows) +
                         " chessboard (inner corners) found in the image; check --board and that "
                         "the whole board is in view");
  }
  // Subpixel refinement with a window well inside the smallest square seen.
  double min_spacing = 1e9;
  for (int j = 0; j < spec.rows; ++j) {
    for (int i = 0; i < spec.cols; ++i) {
      const cv::Point2f p = corners[j * spec.cols + i];
      if (i + 1 < spec.cols)
        min_spacing = std::min<double>(min_spacing, cv::norm(p - corners[j * spec.cols + i + 1]));
      if (j + 1 < spec.rows)
        min_spacing = std::min<double>(min_spacing, cv::norm(p - corners[(j + 1) * spec.cols + i]));
    }
  }
  const int half_window = std::clamp(static_cast<int>(min_spacing * 0.4), 2, 11);
  const cv::TermCriteria criteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4);
  cv::cornerSubPix(grey, corners, cv::Size(half_window, half_window), cv::Size(-1, -1), criteria);
  // cornerSubPix can slide to a neighbouring feature on a foreshortened, blurred board
  // (measured: single corners 2.6-5.5 px off on views tilted ~37 degrees with 13 px squares,
  // which then dominate a calibration). A corner far from where its neighbours put it is
  // refined again from there with half the window, and keeps whichever of the two
  // refinements agrees better with its neighbours.
  const float max_disagreement_px = std::max(1.0f, static_cast<float>(0.1 * min_spacing));
  for (int j = 0; j < spec.rows; ++j) {
    for (int i = 0; i < spec.cols; ++i) {
      const size_t idx = j * spec.cols + i;
      const cv::Point2f expected = PredictFromNeighbours(corners, spec.cols, spec.rows, i, j);
      if (cv::norm(corners[idx] - expected) <= max_disagreement_px) continue;
      std::vector<cv::Point2f> again{expected};
      const int small = std::max(2, half_window / 2);
      cv::cornerSubPix(grey, again, cv::Size(small, small), cv::Size(-1, -1), criteria);
      if (cv::norm(again[0] - expected) < cv::norm(corners[idx] - expected))
        corners[idx] = again[0];
    }
  }

  // Directions of the detector's two index axes in the image.
  const cv::Point2f along_row = corners[spec.cols - 1] - corners[0];
  const cv::Point2f along_col = corners[(spec.rows - 1) * spec.cols] - corners[0];
  // x_p follows the index axis that is more horizontal in the image.
  const bool swap_axes = std::abs(along_col.x) / (cv::norm(along_col) + 1e-9) >
                         std::abs(along_row.x) / (cv::norm(along_row) + 1e-9);
  const cv::Point2f x_dir = swap_axes ? along_col : along_row;
  const cv::Point2f y_dir = swap_axes ? along_row : along_col;
  const bool flip_x = x_dir.x < 0;  // x_p must run to the right (+u)
  const bool flip_y = y_dir.y > 0;  // y_p must run away from the camera (-v)

  BoardObservation out;
  out.cols = swap_axes ? spec.rows : spec.cols;
  out.rows = swap_axes ? spec.cols : spec.rows;
  out.square_m = spec.square_m;
  out.pixels.resize(corners.size());
  for (int j = 0; j < out.rows; ++j) {
    for (int i = 0; i < out.cols; ++i) {
      const int bi = flip_x ? out.cols - 1 - i : i;  // index along the detector's x-axis
      const int bj = flip_y ? out.rows - 1 - j : j;
      const int detector_col = swap_axes ? bj : bi;
      const int detector_row = swap_axes ? bi : bj;
      const cv::Point2f p = corners[detector_row * spec.cols + detector_col];
      out.pixels[j * out.cols + i] = Eigen::Vector2d(p.x, p.y);
    }
  }
  return out;
}

}  // namespace monocle
