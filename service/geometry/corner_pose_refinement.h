// The corner pose refined on the edges' points (nonlinear least squares after the closed
// form, corner_pose.h), with its covariance and each edge's share of it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "service/common/result.h"
#include "service/geometry/corner_pose.h"

namespace monocle {

// Edge points of one corner line, in OpenCV normalized (undistorted) coordinates,
// summarised by their centroid, principal direction and spread.
struct LineObservation {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // unit, away from the corner
  double spread = 0;  // standard deviation of the points along the line
  int num_points = 0;
  // Optional, for the covariance: 1 sigma of one edge point across the line (pixels), and how
  // many of the points are independent (neighbouring samples that share image data are not).
  // 0: the common point_sigma_px of RefineCornerPose, and num_points.
  double point_sigma_px = 0;
  double independent_points = 0;
  // Optional, for the covariance only: the scatter of this line's points as measured (pixels).
  // The fit keeps the weights above; the covariance then propagates each line's own noise
  // through them (a sandwich), so a short, faint edge among two strong ones is not credited
  // with their precision. 0: the noise the weights assume.
  double scatter_sigma_px = 0;
  // Optional, for the covariance only: how much less certain the line's direction is than
  // its points' spread says (>= 1; its offset keeps the scatter above). Points that lean
  // towards where the search started rather than the edge (a faded stretch) are kept in the
  // fit but must not narrow the direction.
  double direction_sigma_scale = 1;
};

struct CornerRefinement {
  CornerPose pose;
  Eigen::Matrix<double, 5, 5> covariance;  // (x, y, pan, tilt, swing): m^2, rad^2
  double rms_px = 0;                       // RMS line residual after refinement, pixels
  // What each line's noise (and bias) adds to var(x) + var(y), m^2. The covariance is a sum
  // over the lines (each line's residuals are independent of the others'), so these add up
  // to covariance(0, 0) + covariance(1, 1): which edge limits the position, and how much.
  std::array<double, 3> horizontal_variance_m2_by_line{};
};

// Nonlinear least squares of (x, y, pan, tilt, swing) on the line observations (z fixed),
// from `initial`; covariance for edge-point noise `point_sigma_px` (or each line's own, see
// LineObservation). `focal_px` converts
// normalized units to pixels. `axis_of_line[k]` names the axis line k images.
// `line_bias_px`: 1 sigma of an offset of each line as a whole (shading across the edge,
// compression, blur), which more points do not average away; added to the covariance
// through the same Jacobian.
// The six weighted residuals RefineCornerPose minimises (two per line, pixels times each
// line's weight) at `pose`; empty where an axis does not image in front of the camera.
std::optional<Eigen::Matrix<double, 6, 1>> CornerLineResiduals(
    const CornerPose& pose, const std::array<LineObservation, 3>& lines,
    const std::array<int, 3>& axis_of_line, double focal_px, double point_sigma_px);

Result<CornerRefinement> RefineCornerPose(const CornerPose& initial,
                                          const std::array<LineObservation, 3>& lines,
                                          const std::array<int, 3>& axis_of_line, double focal_px,
                                          double point_sigma_px, double line_bias_px = 0);

}  // namespace monocle
