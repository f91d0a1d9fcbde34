// Edges measured across their profile, to subpixel precision: the steepest rise of an
// intensity profile across an edge, averaged along it (the image's noise, which an edge is
// judged against, is image_noise.h). Used by the corner
// detector, the locator's second pass and the tracker.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "service/vision/image_noise.h"

namespace monocle {

// Each edge point comes from a profile averaged over 7 px along the edge: points closer
// than that share image data. The fraction of independent ones is spacing / 7 px.
inline constexpr double kProfileWindowPx = 7.0;

// Subpixel edge points near predicted positions: for each (position, unit normal) the
// intensity profile along the normal, averaged over +-3 px along the edge (so a step of a few
// grey levels stands out of the noise), its steepest rise within +-half_width_px refined by a
// parabola. `polarity` +1 or -1: the sign the derivative must have; 0: either, whichever
// is steeper at that place. A point is kept when the step across it (over +-3 px) is at
// least `min_step_grey`, and neither side is clipped (averaging >= 250 or <= 5 grey: a
// saturated surface moves the steepest rise off the edge). Misses are skipped.
//
// `derivative_sigma_px` 0: the derivative is the central difference smoothed by [1 2 1] / 4,
// right for sharp edges; > 0: a derivative of a Gaussian of that sigma, for a blurred edge
// (sigma = its blur is the matched filter; the locator uses a wider one,
// EdgeDerivativeSigmaPx).
struct EdgePointSample {
  Eigen::Vector2d point_px;
  double step_grey = 0;          // signed along the normal
  double slope_grey_per_px = 0;  // the derivative's peak (magnitude), as filtered
};
std::vector<EdgePointSample> MeasureEdgePoints(const cv::Mat& grey,
                                               const std::vector<Eigen::Vector2d>& positions_px,
                                               const std::vector<Eigen::Vector2d>& normals,
                                               double half_width_px, int polarity,
                                               double min_step_grey,
                                               double derivative_sigma_px = 0);

// The same along a straight stretch: `count` positions from `start`, `spacing_px` apart
// along `direction` (unit), normals its left normal (-d.y, d.x). Sampled from one rotated
// patch: several times faster than MeasureEdgePoints, same result up to interpolation.
std::vector<EdgePointSample> MeasureEdgeStretch(const cv::Mat& grey, const Eigen::Vector2d& start,
                                                const Eigen::Vector2d& direction, int count,
                                                int spacing_px, double half_width_px, int polarity,
                                                double min_step_grey,
                                                double derivative_sigma_px = 0);

// The blur of an edge, pixels (the sigma of a Gaussian-blurred step), from samples measured
// with the default filter: a step S blurred by sigma rises at most S / (sigma sqrt(2 pi)).
// The median over the samples; 0 when there are none.
double EdgeBlurSigmaPx(const std::vector<EdgePointSample>& samples);

// The derivative filter's sigma for measuring an edge of this blur (pixels): 0 (the default
// filter) for an edge blurred by 0.8 px or less, else 1.6x the blur: wider than the filter
// matched to the blur, which detects a blurred step in noise best but locates it less
// precisely (client/cli/GUIDE.md, "The derivative filter's width").
double EdgeDerivativeSigmaPx(double blur_sigma_px);

// The filter for a weakly determined view, whose edges are measured again and the shading
// across them read and its shift removed (CornerQualityOptions::
// shading_check_above_relative_sigma): 1.9x the blur, nearer the width at which a derivative
// of a Gaussian locates a blurred step best; the correction removes most of its larger
// shading bias. 0 for an edge blurred by 0.8 px or less.
double WeakViewEdgeDerivativeSigmaPx(double blur_sigma_px);

// The shading of the two surfaces beside a straight stretch of an edge, from the stretch's
// mean profile across it: `direction` (unit) runs along the edge from `start` for `length_px`,
// and each side, between `inner_px` and `outer_px` off the edge along the left normal
// (-d.y, d.x) and against it, is fitted with a straight line (least squares over 1 px steps,
// the profile averaged every 2 px along the stretch). Levels are extrapolated to the edge (grey
// levels); slopes are grey levels per pixel along the normal. nullopt when a sample falls off
// the image or on a clipped pixel (>= 250 or <= 5 grey), whose shading is not the surface's.
struct SurfaceShading {
  double level_left = 0, level_right = 0;  // left: against the normal, right: along it
  double slope_left = 0, slope_right = 0;
};
std::optional<SurfaceShading> MeasureShadingAcrossStretch(const cv::Mat& grey,
                                                          const Eigen::Vector2d& start,
                                                          const Eigen::Vector2d& direction,
                                                          double length_px, double inner_px,
                                                          double outer_px);

// How far the shading moves the derivative's peak along the normal (pixels): a step S blurred
// by b, with a slope c_left on one side and c_right on the other, filtered by a derivative of a
// Gaussian of sigma f, peaks where S u / s^2 = c_right - c_left, s^2 = b^2 + f^2 (+ the
// sampler's own width): exactly, since the slopes' kink is blurred like the step. So
//     shift = (c_right - c_left) s^2 / S,
// the same along the whole stretch, which its points do not average away. `blur_sigma_px` as
// EdgeBlurSigmaPx gives it, `derivative_sigma_px` as MeasureEdgeStretch takes it (0: the
// default filter). 0 when the step is under 1e-3 grey levels.
double ShadingPeakShiftPx(const SurfaceShading& shading, double blur_sigma_px,
                          double derivative_sigma_px);

// One short stretch of an edge (a chunk of neighbouring samples): keeps the points whose
// step has the sign most of them have, none if fewer than 3 agree. Along one edge the
// contrast may fade and change sign where shading evens the two surfaces out.
std::vector<EdgePointSample> MajoritySign(std::vector<EdgePointSample> samples);

}  // namespace monocle
