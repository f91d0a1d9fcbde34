#include "service/vision/support_assessment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "service/vision/corner_rays.h"
#include "service/vision/edge_profile.h"

namespace monocle {
namespace {

// The edges' steps are compared this close to the corner (pixels), before shading along
// them changes the surfaces' brightness.
constexpr double kStepNearCornerPx = 100;

// How a reason of imprecision alone begins (IsImprecisionReason).
constexpr char kImprecisionPrefix[] = "position uncertain: ";

// Length of an axis's image from the corner to where it leaves the image, pixels.
double VisibleLengthPx(const CameraIntrinsics& k, const CornerPose& pose, int axis,
                       const Eigen::Vector2d& corner_px) {
  const double scale = std::max(CameraPosition(pose).norm(), 0.1);
  // The axis in the camera frame: c + t * along (the rotation computed once, not per step).
  const Eigen::Vector3d c = CornerToCamera(pose, Eigen::Vector3d::Zero());
  const Eigen::Vector3d along = RotationCameraFromCorner(pose).col(axis);
  // The pixel of the point t along the axis, if it is in front of the camera and in the image.
  auto visible_px = [&](double t) -> std::optional<Eigen::Vector2d> {
    const Eigen::Vector3d p = c + t * along;
    if (p.z() <= 1e-3 * scale) return std::nullopt;
    const Eigen::Vector2d px = NormalizedToPixel(k, p.head<2>() / p.z());
    if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1)
      return std::nullopt;
    return px;
  };
  // Out along the axis in 2 % steps until it leaves the view; only the last visible step
  // counts, so every 8th step is projected, then the steps of the last stretch one by one.
  std::vector<double> steps;
  for (double t = 1e-3 * scale; t < 100 * scale; t *= 1.02) steps.push_back(t);
  constexpr size_t kStride = 8;
  size_t visible = 0;                   // steps [0, visible) are known to be visible
  std::optional<Eigen::Vector2d> last;  // the last visible step's pixel
  while (visible + kStride <= steps.size()) {
    const auto px = visible_px(steps[visible + kStride - 1]);
    if (!px) break;
    last = px;
    visible += kStride;
  }
  for (size_t i = visible; i < steps.size(); ++i) {
    const auto px = visible_px(steps[i]);
    if (!px) break;
    last = px;
  }
  return last ? (*last - corner_px).norm() : 0.0;
}

std::string Format(const char* format, double a, double b = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

// Each edge's step near the corner (grey levels): the median |step| of its points within
// `radius_px` of the corner (all its points when fewer than 5 lie there).
double StepNearCornerGrey(const LineFit& fit, const Eigen::Vector2d& corner_n, double focal,
                          double radius_px) {
  std::vector<double> near, all;
  for (size_t i = 0; i < fit.inliers.size(); ++i) {
    all.push_back(std::abs(fit.inlier_steps[i]));
    if ((fit.inliers[i] - corner_n).norm() * focal <= radius_px) near.push_back(all.back());
  }
  std::vector<double>& v = near.size() >= 5 ? near : all;
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Why the pose is suspect for an edge leaving the corner that is not one of the Y's, stronger
// than the Y's weakest (empty if none is): see corner_rays.h.
std::string OtherRayReason(const OtherRay& other, const Eigen::Vector2d& corner_px,
                           double noise_grey, const CornerQualityOptions& quality) {
  if (!(other.step_grey > quality.min_other_ray_noise_sigmas * noise_grey)) return "";
  // The weakest edge the rings could read (an edge shorter than the smallest ring is not).
  int weakest = -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (other.edge_step_grey[axis] > 0 &&
        (weakest < 0 || other.edge_step_grey[axis] < other.edge_step_grey[weakest]))
      weakest = axis;
  }
  if (weakest < 0 || other.step_grey <= quality.max_other_ray_ratio * other.edge_step_grey[weakest])
    return "";
  const Eigen::Vector2d towards_px = OtherEdgeTowardsPx(corner_px, other.angle_rad);
  return Format("an edge of %.0f grey levels leaves the corner", other.step_grey) +
         Format(" towards (%.0f, %.0f) px, stronger than", towards_px.x(), towards_px.y()) +
         std::string(" edge ") + "XYZ"[weakest] +
         Format("'s %.1f: one of the corner's edges taken for another?",
                other.edge_step_grey[weakest]);
}

// Per-edge support against the refined pose, and whether to call the pose suspect.
// Which edge most of an imprecise pose's variance comes from, with what makes it weak, e.g.
// ", 84 % of its variance from edge Y: 91 px long, contrast 14.6 grey levels at noise 2.6";
// empty when no edge gives half of it.
std::string LimitingEdgeClause(const CornerLocation& location) {
  int limiting = 0;
  for (int axis = 1; axis < 3; ++axis)
    if (location.support[axis].position_variance_share >
        location.support[limiting].position_variance_share)
      limiting = axis;
  const EdgeSupport& s = location.support[limiting];
  if (s.position_variance_share < 0.5) return "";
  return Format(", %.0f %% of its variance from edge ", 100 * s.position_variance_share) +
         "XYZ"[limiting] + Format(": %.0f px long, ", s.length_px) +
         Format("contrast %.1f grey levels at noise %.1f", s.contrast_grey,
                location.noise_sigma_grey);
}

// When the shading beside the edges gives a quarter or more of the horizontal variance, how
// far it moved the position, e.g. ", the shading beside the edges moved it 1.3 % of the
// distance (corrected, and counted in the 1 sigma)"; empty otherwise.
std::string ShadingClause(const CornerLocation& location) {
  const double shift2 = location.shading_shift.head<2>().squaredNorm();
  const double variance = location.covariance(0, 0) + location.covariance(1, 1);
  if (!(shift2 >= 0.25 * variance) || shift2 == 0) return "";
  return Format(", the shading beside the edges moved it %.1f %% of the distance",
                100 * std::sqrt(shift2) / std::hypot(location.pose.x_m, location.pose.y_m)) +
         " (corrected, and counted in the 1 sigma)";
}

}  // namespace

namespace {

// One edge's support against the pose in `out` (its EdgeSupport, line end and points), and
// why it fails to support it, added to `reasons`. `c2`: the corner in normalized coordinates
// as the pose projects it. Returns the sum of the squared distances of the edge's points to
// the pose's line (pixels^2), for the overall RMS.
double MeasureEdgeSupport(const CameraIntrinsics& k, const LineFit& fit, int axis,
                          const Eigen::Vector2d& corner_n, const Eigen::Vector2d& c2,
                          double spacing_px, const CornerQualityOptions& quality,
                          CornerLocation* out, Eigen::Vector2d* direction_px,
                          std::vector<std::string>* reasons) {
  const double focal = 0.5 * (k.fx + k.fy);
  const char* kAxis = "XYZ";
  EdgeSupport& s = out->support[axis];
  const Eigen::Vector3d a = CornerToCamera(
      out->pose, 1e-3 * CameraPosition(out->pose).norm() * Eigen::Vector3d::Unit(axis));
  const Eigen::Vector2d dir = (a.head<2>() / a.z() - c2).normalized();
  const Eigen::Vector2d normal(-dir.y(), dir.x());
  *direction_px = (NormalizedToPixel(k, c2 + 1e-3 * dir) - out->corner_px).normalized();
  // Unweighted for the reported RMS; weighted as the fit was for the misfit below.
  double edge_sum2 = 0, weighted_sum2 = 0, weights = 0;
  for (size_t i = 0; i < fit.inliers.size(); ++i) {
    const double d2 = std::pow(normal.dot(fit.inliers[i] - c2) * focal, 2);
    const double w = fit.inlier_weights.empty() ? 1.0 : fit.inlier_weights[i];
    edge_sum2 += d2;
    weighted_sum2 += w * d2;
    weights += w;
  }
  // The edge runs from the corner as far as its points follow each other: a stray point
  // far out on the line (noise or shading that happens to line up) is not where it ends.
  std::vector<std::pair<double, Eigen::Vector2d>> by_distance;
  for (const auto& p : fit.inliers) by_distance.push_back({(p - corner_n).norm() * focal, p});
  std::sort(by_distance.begin(), by_distance.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  const double max_gap_px = MaxGapPx(spacing_px);
  Eigen::Vector2d far = by_distance.front().second;
  for (size_t i = 1; i < by_distance.size(); ++i) {
    if (by_distance[i].first - by_distance[i - 1].first > max_gap_px) break;
    far = by_distance[i].second;
  }
  s.points = static_cast<int>(fit.inliers.size());
  s.rms_px = std::sqrt(edge_sum2 / std::max(s.points, 1));
  out->line_end_px[axis] = NormalizedToPixel(k, far);
  out->points_per_line[axis] = s.points;
  s.length_px = (out->line_end_px[axis] - out->corner_px).norm();
  s.visible_length_px = VisibleLengthPx(k, out->pose, axis, out->corner_px);
  // Points are spacing_px apart from 8 px off the corner.
  s.coverage = std::min(1.0, spacing_px * s.points / std::max(s.visible_length_px - 8, 2.0));
  std::vector<double> steps;
  for (double step : fit.inlier_steps) steps.push_back(std::abs(step));
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  s.contrast_grey = steps.empty() ? 0 : steps[steps.size() / 2];
  s.contrast_to_noise = s.contrast_grey / std::max(out->noise_sigma_grey, 0.5);
  const double independent = std::max(2.0, s.points * std::min(1.0, spacing_px / kProfileWindowPx));
  s.sigma_px = fit.normal_rms * focal / std::sqrt(independent);
  // Scatter about the pose's line = scatter about its own line + the lines' separation,
  // both weighted as the fit weighs its points.
  const double own_rms_px = fit.normal_rms * focal;
  const double pose_rms2 = weighted_sum2 / std::max(weights, 1e-9);
  s.misfit_px = std::sqrt(std::max(0.0, pose_rms2 - own_rms_px * own_rms_px));
  const double allowed =
      std::max(quality.min_edge_misfit_px,
               quality.max_edge_misfit_sigmas * std::hypot(s.sigma_px, kLineBiasPx));
  const std::string edge = std::string("edge ") + kAxis[axis];
  if (s.coverage < quality.min_coverage)
    reasons->push_back(edge + Format(" found on %.0f %% of its visible length", 100 * s.coverage));
  if (s.contrast_to_noise < quality.min_contrast_to_noise)
    reasons->push_back(edge + Format(" contrast %.1f grey levels at noise %.1f", s.contrast_grey,
                                     out->noise_sigma_grey));
  if (s.misfit_px > allowed)
    reasons->push_back(
        edge + Format(" lies %.2f px off the pose's line (allowed %.2f)", s.misfit_px, allowed));
  return edge_sum2;
}

}  // namespace

void AssessSupport(const cv::Mat& grey, const CameraIntrinsics& k,
                   const std::array<LineFit, 3>& fits, const std::array<int, 3>& axis_of_line,
                   const Eigen::Vector2d& corner_n, const CornerQualityOptions& quality,
                   const std::array<double, 3>& spacing_px, CornerLocation* out) {
  const double focal = 0.5 * (k.fx + k.fy);
  const Eigen::Vector3d c_cam = CornerToCamera(out->pose, Eigen::Vector3d::Zero());
  const Eigen::Vector2d c2 = c_cam.head<2>() / c_cam.z();
  std::vector<std::string> reasons;
  std::array<Eigen::Vector2d, 3> direction_px;  // X, Y, Z leaving the corner, image pixels
  double sum2 = 0;
  int total = 0;
  for (int m = 0; m < 3; ++m) {
    const int axis = axis_of_line[m];
    sum2 += MeasureEdgeSupport(k, fits[m], axis, corner_n, c2, spacing_px[m], quality, out,
                               &direction_px[axis], &reasons);
    total += static_cast<int>(fits[m].inliers.size());
  }
  std::array<double, 3> steps_near_corner;
  for (int m = 0; m < 3; ++m)
    steps_near_corner[m] = StepNearCornerGrey(fits[m], corner_n, focal, kStepNearCornerPx);
  std::sort(steps_near_corner.begin(), steps_near_corner.end());
  const double excess = steps_near_corner[2] - steps_near_corner[1] - steps_near_corner[0];
  if (steps_near_corner[2] > 0 && excess > quality.max_step_excess * steps_near_corner[2]) {
    reasons.push_back(Format("the edges' steps do not add up: %.1f grey levels across one, ",
                             steps_near_corner[2]) +
                      Format("%.1f + %.1f across the others (at a corner one equals the other two)",
                             steps_near_corner[1], steps_near_corner[0]));
  }
  const OtherRay other = StrongestOtherRay(grey, out->corner_px, direction_px);
  out->other_edge_angle_rad = other.angle_rad;
  out->other_edge_step_grey = other.step_grey;
  if (auto why = OtherRayReason(other, out->corner_px, out->noise_sigma_grey, quality);
      !why.empty()) {
    out->other_edge_flagged = true;
    reasons.push_back(std::move(why));
  }
  if (std::abs(out->pose.swing_rad) > quality.max_swing_rad) {
    reasons.push_back(
        Format("the camera would be rolled %.0f degrees about its axis (more than "
               "%.0f): a floor corner or another Y taken for the ceiling's?",
               out->pose.swing_rad * 180 / std::numbers::pi,
               quality.max_swing_rad * 180 / std::numbers::pi));
  }
  out->rms_px = std::sqrt(sum2 / std::max(total, 1));
  const bool edges_agree = reasons.empty();
  if (auto imprecise = ImprecisionReason(out->pose, out->covariance, quality); !imprecise.empty())
    reasons.push_back(std::move(imprecise) + LimitingEdgeClause(*out) + ShadingClause(*out));
  out->suspect = !reasons.empty();
  out->suspect_only_imprecise = out->suspect && edges_agree;
  out->suspect_reason.clear();
  for (const auto& r : reasons)
    out->suspect_reason += (out->suspect_reason.empty() ? "" : "; ") + r;
}

std::string ImprecisionReason(const CornerPose& pose, const Eigen::Matrix<double, 5, 5>& covariance,
                              const CornerQualityOptions& quality, const std::string& qualifier) {
  const double horizontal = std::hypot(pose.x_m, pose.y_m);
  const double sigma_h = std::sqrt(covariance(0, 0) + covariance(1, 1));
  if (!(sigma_h > quality.max_relative_sigma * horizontal)) return "";
  return kImprecisionPrefix +
         Format("1 sigma %.1f %% of the distance", 100 * sigma_h / horizontal) +
         (qualifier.empty() ? "" : " " + qualifier) +
         Format(" (more than %.3g)", 100 * quality.max_relative_sigma);
}

bool IsImprecisionReason(const std::string& reason) {
  return reason.starts_with(kImprecisionPrefix);
}

}  // namespace monocle
