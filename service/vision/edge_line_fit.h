// Straight lines through an edge's points, as the corner locator fits them: total least
// squares weighted by each point's contrast, with robust rejection (the paper's eq. 17), and
// the corner where three fitted lines meet (section 3.5).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

namespace monocle {

// A line fitted to an edge's points: through `centroid` along `direction` (unit), with the
// points it kept.
struct LineFit {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero(), direction = Eigen::Vector2d::UnitX();
  std::vector<Eigen::Vector2d> inliers;  // normalized coordinates
  std::vector<double> inlier_steps;      // grey levels, as measured at each inlier
  std::vector<double> inlier_weights;    // relative weight of each inlier in the fit
  double normal_rms = 0;                 // normalized units
};

// How much less a line's points tell about its direction when only those that follow each
// other from the corner count (no gap over max_gap_px): the ratio of sqrt(n) * spread of
// all points to that of the contiguous ones (>= 1; 1 without a gap). Beyond a gap the edge has
// faded below the noise; what the second pass finds there is the steepest noise in its window
// around the first pass's line, so those points lean towards that line's error and have the most
// leverage on the direction. They stay in the fit (on a well-seen edge they are the edge),
// but not in its precision.
double BeyondGapLeverage(const LineFit& fit, const Eigen::Vector2d& corner, double focal,
                         double max_gap_px);

// Total least squares (the paper's eq. 17) with iterative rejection of points further than
// 3 robust sigmas: clutter crossing the edge, or the edge ending.
//
// Each point is weighted by its step squared (relative to the median, within 1/4-4x): a
// point's noise across the edge is the image noise over the contrast it sits on, and along
// a white room's edge that contrast fades and grows with shading, vignetting and the lamp's
// hot-spot. Equal weights let the faded stretches' noisy points set the direction. Measured
// across 16 noise draws of single views (corner_accuracy_test's development harness), the
// pose scatter fell by up to two fifths where the contrast varies along an edge, and did not
// grow elsewhere. Distances are compared with the rejection threshold in weighted units.
std::optional<LineFit> RobustLineFit(std::vector<Eigen::Vector2d> pts, std::vector<double> steps,
                                     double floor_sigma);

// An edge runs from the corner as far as its points follow each other, gaps up to this.
double MaxGapPx(double spacing_px);

// Where two fitted lines cross; nothing for parallel lines.
std::optional<Eigen::Vector2d> IntersectLines(const LineFit& a, const LineFit& b);

// Section 3.5: the corner is the centre of the three pairwise intersections. Each
// intersection is weighted by sin^2 of its lines' angle: a Y often has two nearly collinear
// edges whose intersection slides along them; with well separated lines this is the paper's
// plain centre.
std::optional<Eigen::Vector2d> ConstrainedCorner(const std::array<LineFit, 3>& fits);

}  // namespace monocle
