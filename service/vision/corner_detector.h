// Finds the three edges of a ceiling corner (a "Y") in a grey image: the paper's section 3
// (Sobel edges, thinning, Hough transform with smoothed counts H', the Y checks, least
// squares fits, constrained refit), made subpixel and robust to clutter.
//
// Detection runs at a quarter of the resolution, then at half when no Y found there is
// accepted; edge points are then measured at full resolution, to subpixel precision, along
// each detected edge.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/vision/edge_profile.h"

namespace monocle {

struct CornerDetectorOptions {
  // Edges are decided relative to the image's own noise, not by constants: an edge pixel's
  // gradient (half resolution, after a Gaussian of sigma 1) must exceed `edge_snr` times
  // the gradient noise estimated from the image, and at least `min_edge_gradient`.
  double edge_snr = 3.0;
  double min_edge_gradient = 8;    // Sobel units, ~3 grey levels of step; for noiseless images
  int max_lines = 80;              // Hough peaks considered
  double min_edge_length_px = 60;  // shortest corner edge, full resolution
  double junction_radius_px = 12;  // how far apart the pairwise intersections may be
  // Edge points at full resolution: step across the edge at least this many noise sigmas,
  // and at least `min_step_grey`.
  double min_step_snr = 1.0;
  double min_step_grey = 1.5;
  // Look for the Y at a quarter of the resolution first (images >= 800 px on each side),
  // then at half when nothing found there is accepted. False: half only.
  bool quarter_resolution_first = true;
  // Edge points along each edge's trace from the corner to the border, every this many
  // pixels (full resolution). The trace only guides the locator's second pass, which
  // measures the edge again every 2 px along the line fitted to the trace: every 4 px is as
  // accurate and takes a tenth less time per frame (bench/corner_speed_notes.md).
  int trace_spacing_px = 4;
  // The second pass's points, pixels apart along the fitted line. Each point's profile spans
  // 7 px along the edge (kProfileWindowPx), so points 2 px apart share most of their pixels:
  // the tracker measures every 6 px, a third of the work for nearly the same information.
  int measure_spacing_px = 2;
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
  std::array<std::vector<double>, 3> step_grey;  // signed step across the edge at each point
  std::array<int, 3> polarity{};  // sign of the intensity derivative along the left normal
  // Each edge's blur, pixels (EdgeBlurSigmaPx of its points; 0: not measured): the locator
  // measures a blurred edge with a wider derivative filter.
  std::array<double, 3> blur_sigma_px{};
  // The image's noise, grey levels (1 sigma), two ways. Pixel to pixel (EstimateNoiseSigma):
  // the detector's step thresholds were set against it. As a measurement averaging pixels
  // sees it (EstimateMeasurementNoiseSigma): what an edge's contrast is judged against and
  // what is reported. They agree on a raw image; after JPEG the second is 2-5x the first.
  double noise_sigma_grey = 0;
  double measurement_noise_grey = 0;
  double sample_spacing_px = 2;  // distance between neighbouring edge points along an edge
  // The resolution the Y was found at, relative to the image: 0.25 (a quarter, tried first
  // on images at least 800 px on each side), 0.5, or 1 (small images). Edge points are
  // always measured at full resolution. 0: not detected (the tracker predicted the edges).
  double detection_scale = 0;
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

// Every Y worth trying (up to 10), best supported first, each measured as DetectCornerEdges
// does and handed to `accept` until it returns true: a Y the image supports may still be
// rejected by the pose (not a corner seen from inside a room), and then the next one is the
// corner. Returns why none was accepted (the first reason), or nothing when one was.
std::optional<Error> ForEachCornerCandidate(const cv::Mat& grey,
                                            const CornerDetectorOptions& options,
                                            const CameraIntrinsics* intrinsics,
                                            const std::function<bool(CornerEdges)>& accept);

// The straight edges the Hough stage finds (full-resolution pixels), for overlays and
// diagnosis when no corner is found.
std::vector<HoughSegment> DetectStraightEdges(const cv::Mat& grey,
                                              const CornerDetectorOptions& options = {},
                                              const CameraIntrinsics* intrinsics = nullptr);

// The weakest step an edge point may have in this image (options and noise).
double MinStepGrey(const CornerDetectorOptions& options, double noise_sigma_grey);

}  // namespace monocle
