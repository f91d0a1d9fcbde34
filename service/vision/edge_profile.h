// Edges measured across their profile, to subpixel precision: the image's noise, and the
// steepest rise of an intensity profile across an edge, averaged along it. Used by the corner
// detector, the locator's second pass and the tracker.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace monocle {

// Pixel noise of an image, grey levels (1 sigma): from the median absolute difference of
// horizontally adjacent pixels, which flat surfaces dominate in a room. Never much below
// 8-bit quantization (~0.26 for a constant image).
double EstimateNoiseSigma(const cv::Mat& grey);

// Subpixel edge points near predicted positions: for each (position, unit normal) the
// intensity profile along the normal, averaged over +-3 px along the edge (so a step of a few
// grey levels stands out of the noise), its steepest rise within +-half_width_px refined by a
// parabola. `polarity` +1 or -1: the sign the derivative must have; 0: either, whichever
// is steeper at that place. A point is kept when the step across it (over +-3 px) is at
// least `min_step_grey`, and neither side is clipped (averaging >= 250 or <= 5 grey: a
// saturated surface moves the steepest rise off the edge). Misses are skipped.
struct EdgePointSample {
  Eigen::Vector2d point_px;
  double step_grey = 0;  // signed along the normal
};
std::vector<EdgePointSample> MeasureEdgePoints(const cv::Mat& grey,
                                               const std::vector<Eigen::Vector2d>& positions_px,
                                               const std::vector<Eigen::Vector2d>& normals,
                                               double half_width_px, int polarity,
                                               double min_step_grey);

// The same along a straight stretch: `count` positions from `start`, `spacing_px` apart
// along `direction` (unit), normals its left normal (-d.y, d.x). Sampled from one rotated
// patch: several times faster than MeasureEdgePoints, same result up to interpolation.
std::vector<EdgePointSample> MeasureEdgeStretch(const cv::Mat& grey, const Eigen::Vector2d& start,
                                                const Eigen::Vector2d& direction, int count,
                                                int spacing_px, double half_width_px, int polarity,
                                                double min_step_grey);

// One short stretch of an edge (a chunk of neighbouring samples): keeps the points whose
// step has the sign most of them have, none if fewer than 3 agree. Along one edge the
// contrast may fade and change sign where shading evens the two surfaces out.
std::vector<EdgePointSample> MajoritySign(std::vector<EdgePointSample> samples);

}  // namespace monocle
