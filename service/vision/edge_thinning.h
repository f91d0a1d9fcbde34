// The corner detector's first stage: Sobel gradients thinned to one-pixel-wide edges by
// non-maximum suppression across them, with a threshold that follows the image's noise.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "service/vision/corner_detector.h"

namespace monocle::corner_detection {

inline constexpr int kAngleBins = 360;         // Hough angle bins over 180 degrees: 0.5 degree
inline constexpr int kMinVoteHalfWindow = 4;   // +-2 degrees around the gradient's direction
inline constexpr int kMaxVoteHalfWindow = 20;  // +-10 degrees for the weakest edges

struct EdgePixel {
  float x, y;                // half-resolution pixel
  float nx, ny;              // unit gradient
  int vote_half_window = 4;  // Hough angle bins either side of the gradient's direction
  float angle = 0;           // atan2(ny, nx), radians: set once the gradient is final
};

// Sobel, then non-maximum suppression across the edge: the thinning step. The threshold
// follows the image: in flat regions (most of a room) the gradient's two components are
// Gaussian noise, so its squared magnitude is exponential with median 2 ln 2 sigma_g^2.
// The threshold comes from a sample of pixels first (MedianOfNonNegative: the sample's
// nth_element was a third of this function's time), so the squared magnitudes are then
// computed three rows at a time, and only the pixels above it (a few in a hundred) are
// compared with their neighbours. The same edges, in the same order, as before.
std::vector<EdgePixel> ThinEdges(const cv::Mat& img, const CornerDetectorOptions& options);

}  // namespace monocle::corner_detection
