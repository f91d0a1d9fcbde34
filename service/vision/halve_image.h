// An 8-bit grey image halved in each direction: each pixel the mean of a 2 x 2 block,
// rounded, (a + b + c + d + 2) / 4, pixel for pixel what cv::resize(..., 0.5, 0.5,
// INTER_AREA) gives (halve_image_test), only faster on a frame fresh from the camera.
//
// Why not cv::resize: halving a 1280 x 1024 frame that is not in the cache took OpenCV
// 0.17 ms, a seventh of a whole corner detection, although reading the frame takes 0.05 ms:
// its loop waits for memory row by row. Here the rows eight ahead are prefetched while a row
// pair is averaged, and the same halving takes 0.08 ms (bench/corner_bench, realistic frames).
#pragma once

#include <opencv2/core.hpp>

namespace monocle {

// `src`: CV_8UC1. Even sizes are halved here; an odd width or height goes to cv::resize,
// whose rounding of the size and of the last column or row this does not copy.
void HalveImage(const cv::Mat& src, cv::Mat* dst);

}  // namespace monocle
