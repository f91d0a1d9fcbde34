// Finds the three edges of a ceiling corner (a "Y") in a grey image: the paper's section 3
// (Sobel edges, thinning, Hough transform with smoothed counts H', the Y checks, least
// squares fits, constrained refit), made subpixel and robust to clutter.
//
// Detection runs at half resolution; edge points are then measured at full resolution,
// to subpixel precision, along each detected edge.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"

namespace monocle {

struct CornerDetectorOptions {
  double edge_threshold = 32;  // Sobel magnitude (3x3) at half resolution; ~10 grey levels of step
  int max_lines = 40;          // Hough peaks considered
  double min_edge_length_px = 60;  // shortest corner edge, full resolution
  double junction_radius_px = 12;  // how far apart the pairwise intersections may be
  double min_step_grey = 4;        // weakest edge contrast measured at full resolution
};

// One image line found by the Hough stage (half resolution is hidden from callers).
struct HoughSegment {
  Eigen::Vector2d a_px, b_px;  // end points, full-resolution pixels
  int support = 0;             // edge pixels on it
};

struct CornerEdges {
  Eigen::Vector2d corner_px = Eigen::Vector2d::Zero();  // from the Hough stage, full resolution
  std::array<Eigen::Vector2d, 3> direction{};           // unit, leaving the corner (pixels)
  // Subpixel edge points along each edge, full-resolution (distorted) pixels. Points on
  // clutter crossing the edge are still here; the fit rejects them.
  std::array<std::vector<Eigen::Vector2d>, 3> points_px;
  std::array<int, 3> polarity{};  // sign of the intensity derivative along the left normal
  std::vector<HoughSegment> hough_segments;  // every segment seen, for overlays
};

// Finds the Y and samples its edges along straight rays from the corner to the image
// border (a caller that knows the lens resamples along the curved line, see
// MeasureEdgePoints).
// With `intrinsics`, edge pixels are undistorted before the Hough transform, so edges bent
// by the lens still vote for one straight line; everything returned is in the image's own
// (distorted) pixels.
Result<CornerEdges> DetectCornerEdges(const cv::Mat& grey, const CornerDetectorOptions& options,
                                      const CameraIntrinsics* intrinsics = nullptr);

// The straight edges the Hough stage finds (full-resolution pixels), for overlays and
// diagnosis when no corner is found.
std::vector<HoughSegment> DetectStraightEdges(const cv::Mat& grey,
                                              const CornerDetectorOptions& options = {},
                                              const CameraIntrinsics* intrinsics = nullptr);

// Subpixel edge points near predicted positions: for each (position, unit normal) the
// intensity derivative along the normal within +-half_width_px, its maximum refined by a
// parabola. `polarity` +1 or -1: the sign the derivative must have. Misses are skipped.
std::vector<Eigen::Vector2d> MeasureEdgePoints(const cv::Mat& grey,
                                               const std::vector<Eigen::Vector2d>& positions_px,
                                               const std::vector<Eigen::Vector2d>& normals,
                                               double half_width_px, int polarity,
                                               double min_step_grey);

}  // namespace monocle
