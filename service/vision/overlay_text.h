// Text on the pictures the command line writes and shows (corner overlays, `monocle view`):
// light letters on a black outline, readable on white walls and dark floors alike, and
// messages wider than the picture broken into lines that stay inside it.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace monocle {

// `text` at `at` (its baseline's left end), outlined in black `thickness + 3` wide.
void PutOutlinedText(cv::Mat& image, const std::string& text, cv::Point at, double scale,
                     const cv::Scalar& colour, int thickness);

// `text` broken at spaces into lines no wider than the picture less `at.x` on both sides,
// drawn from `at` down (a word wider than that keeps a line of its own). Returns the baseline
// for a line below the last one.
int PutWrappedText(cv::Mat& image, const std::string& text, cv::Point at, double scale,
                   const cv::Scalar& colour, int thickness);

}  // namespace monocle
