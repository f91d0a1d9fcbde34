// The corner detector's last stage: subpixel edge points traced from a Y's corner out to the
// image border at full resolution, and the checks for clipped surfaces beside an edge.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "service/vision/edge_profile.h"

namespace monocle::corner_detection {

// Whether the image is clipped (3x3 mean >= 250, or <= 5) on either side of an edge through
// `p` (full-resolution pixel, `normal` across the edge), 4 px off it: the edge cannot be
// measured there (PeakOfProfile leaves such points out) nor its contrast be judged.
bool ClippedAcross(const cv::Mat& grey, const Eigen::Vector2d& p, const Eigen::Vector2d& normal);

// Whether at least 80 % of the points every 8 px from `from` to `to` (full-resolution
// pixels) are ClippedAcross the line between them.
bool ClippedAlong(const cv::Mat& grey, const Eigen::Vector2d& from, const Eigen::Vector2d& to);

// Edge points from the corner outwards to the image border: measured in chunks of 32 px
// along the current line, which is refitted to the points found so far (the last 300 px of
// them) before the next chunk. A Hough direction from a short segment near the corner is a
// degree off; a straight ray would leave a long edge long before the border, and lens
// distortion bends the edge away from any straight ray.
std::vector<EdgePointSample> TraceEdge(const cv::Mat& grey, const Eigen::Vector2d& corner,
                                       Eigen::Vector2d direction, double min_step, int spacing_px);

// Whether a quarter or more of the pixels within 40 px of `center` are clipped (>= 250 or
// <= 5): edge points beside such surfaces are not measured (see edge_profile.cc).
bool SaturatedAround(const cv::Mat& grey, const Eigen::Vector2d& center);

}  // namespace monocle::corner_detection
