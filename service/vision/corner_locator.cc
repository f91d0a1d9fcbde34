#include "service/vision/corner_locator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "service/geometry/corner_pose_refinement.h"
#include "service/geometry/undistortion_grid.h"
#include "service/vision/corner_rays.h"
#include "service/vision/edge_line_fit.h"
#include "service/vision/support_assessment.h"

namespace monocle {
namespace {

// No edge point is measured better than this (1 sigma, pixels), whatever its scatter says.
constexpr double kMinPointSigmaPx = 0.05;
// The shading beside an edge is read over this many pixels of each surface (PoseShiftFromShading),
// and no stretch is taken to move by more than kMaxShadingShiftPx: beyond it the surfaces are
// not the straight lines the prediction assumes (a stretch where the step fades to nothing).
constexpr double kShadingRowsPx = 14;
constexpr double kMaxShadingShiftPx = 1.0;

// Undistorted (normalized) edge points, with the step measured at each: within 1e-6 px of
// the exact inverse (UndistortionGrid::Normalized; a third of PixelToNormalized's time).
void Undistort(const CameraIntrinsics& k, const std::vector<Eigen::Vector2d>& px,
               const std::vector<double>& steps, std::vector<Eigen::Vector2d>* points,
               std::vector<double>* kept_steps) {
  points->clear();
  kept_steps->clear();
  const UndistortionGrid* grid = k.HasDistortion() ? &UndistortionGridFor(k) : nullptr;
  for (size_t i = 0; i < px.size(); ++i) {
    if (const auto n = grid != nullptr ? grid->Normalized(px[i]) : PixelToNormalized(k, px[i])) {
      points->push_back(*n);
      kept_steps->push_back(i < steps.size() ? steps[i] : 0.0);
    }
  }
}

// The detector's points, undistorted from the camera's grid (within 0.01 px of the exact
// inverse, and ~5 % of a realistic frame's time less): enough to place the second pass,
// which measures every point again and is undistorted to 1e-6 px.
void UndistortCoarsely(const CameraIntrinsics& k, const std::vector<Eigen::Vector2d>& px,
                       const std::vector<double>& steps, std::vector<Eigen::Vector2d>* points,
                       std::vector<double>* kept_steps) {
  if (!k.HasDistortion()) return Undistort(k, px, steps, points, kept_steps);
  const UndistortionGrid& grid = UndistortionGridFor(k);
  points->clear();
  kept_steps->clear();
  for (size_t i = 0; i < px.size(); ++i) {
    const Eigen::Vector2d u = grid.Undistort(px[i]);
    points->emplace_back((u.x() - k.cx) / k.fx, (u.y() - k.cy) / k.fy);
    kept_steps->push_back(i < steps.size() ? steps[i] : 0.0);
  }
}

// One 32 px stretch of an edge's second pass: where it was sampled (pixels, `along` unit) and
// which of the edge's points it gave ([first, end) of CornerEdges::points_px[m]).
struct EdgeStretch {
  Eigen::Vector2d start_px = Eigen::Vector2d::Zero(), along = Eigen::Vector2d::UnitX();
  double length_px = 0;
  size_t first = 0, end = 0;
};

// One edge: a first fit of the detector's points, then a second pass along the fitted line
// as the lens bends it, with a narrower window (a straight first pass drifts off a distorted
// edge far from the corner), and the final robust fit. Updates the edge's points (and says
// whether the second pass replaced them, and where each of its stretches lies).
// `measured`: the edge's line as measured before (its points are `edges`'), which the second
// pass then follows instead of a first fit of the points.
std::optional<LineFit> FitEdge(const cv::Mat& grey, const CameraIntrinsics& k, int m,
                               double min_step, int spacing_px, bool wide_filter,
                               const LineFit* measured, CornerEdges* edges, bool* replaced,
                               std::vector<EdgeStretch>* stretches) {
  *replaced = false;
  stretches->clear();
  const double focal = 0.5 * (k.fx + k.fy);
  const double floor_sigma = 0.05 / focal;  // no edge is measured better than 0.05 px
  std::vector<Eigen::Vector2d> points;
  std::vector<double> steps;
  std::optional<LineFit> first;
  if (measured != nullptr) {
    first = *measured;
  } else {
    UndistortCoarsely(k, edges->points_px[m], edges->step_grey[m], &points, &steps);
    first = RobustLineFit(points, steps, floor_sigma);
  }
  if (!first) return std::nullopt;
  const Eigen::Vector2d corner_n = PixelToNormalized(k, edges->corner_px).value_or(first->centroid);
  Eigen::Vector2d dir = first->direction;
  if (dir.dot(first->centroid - corner_n) < 0) dir = -dir;
  const Eigen::Vector2d start = first->centroid + dir * dir.dot(corner_n - first->centroid);
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> position_t;  // where each position lies along the line, normalized
  const size_t most_positions =
      static_cast<size_t>(std::hypot(k.width_px, k.height_px) / spacing_px) + 2;
  positions.reserve(most_positions);
  position_t.reserve(most_positions);
  for (double t = 8.0 / focal; t < 4.0; t += spacing_px / focal) {
    const Eigen::Vector2d px = NormalizedToPixel(k, start + t * dir);
    if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1) break;
    positions.push_back(px);
    position_t.push_back(t);
  }
  // The line's direction in the image at one position (the lens bends it): only a stretch of
  // one position needs it, the others take their chord's.
  auto direction_px_at = [&](size_t i) {
    Eigen::Matrix2d j;
    NormalizedToPixel(k, start + position_t[i] * dir, &j);
    return Eigen::Vector2d((j * dir).normalized());
  };
  // Either sign, decided per 32 px stretch: the contrast may fade and turn along an edge.
  // A blurred edge is measured with a derivative of a Gaussian wider than its blur.
  const double derivative_sigma_px = wide_filter
                                         ? WeakViewEdgeDerivativeSigmaPx(edges->blur_sigma_px[m])
                                         : EdgeDerivativeSigmaPx(edges->blur_sigma_px[m]);
  std::vector<EdgePointSample> second;
  second.reserve(positions.size());
  for (size_t begin = 0; begin < positions.size(); begin += 16) {
    const size_t end = std::min(positions.size(), begin + 16);
    // A 32 px stretch of the lens-bent line is straight to well under 0.1 px.
    const Eigen::Vector2d chord = positions[end - 1] - positions[begin];
    const Eigen::Vector2d along = chord.norm() > 0 ? chord.normalized() : direction_px_at(begin);
    const int count = std::max(1, static_cast<int>(std::lround(chord.norm() / spacing_px)) + 1);
    const auto chunk = MajoritySign(MeasureEdgeStretch(
        grey, positions[begin], along, count, spacing_px, 2.5, 0, min_step, derivative_sigma_px));
    if (!chunk.empty())
      stretches->push_back({positions[begin], along, 1.0 * spacing_px * (count - 1), second.size(),
                            second.size() + chunk.size()});
    second.insert(second.end(), chunk.begin(), chunk.end());
  }
  if (second.size() < 10) stretches->clear();  // the detector's points stay
  if (second.size() >= 10) {
    *replaced = true;
    edges->points_px[m].clear();
    edges->step_grey[m].clear();
    for (const auto& sample : second) {
      edges->points_px[m].push_back(sample.point_px);
      edges->step_grey[m].push_back(sample.step_grey);
    }
  }
  Undistort(k, edges->points_px[m], edges->step_grey[m], &points, &steps);
  auto refit = RobustLineFit(points, steps, floor_sigma);
  if (!refit) return std::nullopt;
  if (refit->direction.dot(refit->centroid - corner_n) < 0) refit->direction = -refit->direction;
  return refit;
}

// The line the pose fit sees of one edge's fitted points.
LineObservation ObserveLine(const LineFit& fit, const Eigen::Vector2d& corner, double spacing_px,
                            double focal) {
  LineObservation obs;
  obs.centroid = fit.centroid;
  obs.direction = fit.direction;
  obs.num_points = static_cast<int>(fit.inliers.size());
  double spread2 = 0, weights = 0;
  for (size_t i = 0; i < fit.inliers.size(); ++i) {
    const double w = fit.inlier_weights.empty() ? 1.0 : fit.inlier_weights[i];
    spread2 += w * std::pow(obs.direction.dot(fit.inliers[i] - obs.centroid), 2);
    weights += w;
  }
  obs.spread = std::sqrt(spread2 / std::max(weights, 1e-9));
  // Each point averages the image over 7 px along the edge and they are 2 px apart: about
  // 2/7 of them carry independent noise.
  obs.independent_points =
      std::max(2.0, obs.num_points * std::min(1.0, spacing_px / kProfileWindowPx));
  // Each line is weighted by its own points' scatter: in a white room one edge's points
  // often scatter 3-8x another's (contrast 10 against 40 grey levels), and with one pooled
  // scatter a short faint edge pulled the corner as hard as a long clear one.
  // Its direction is only as certain as the points that follow each other from the corner
  // make it.
  obs.scatter_sigma_px = std::max(fit.normal_rms * focal, kMinPointSigmaPx);
  obs.point_sigma_px = obs.scatter_sigma_px;
  obs.direction_sigma_scale = BeyondGapLeverage(fit, corner, focal, MaxGapPx(spacing_px));
  return obs;
}

// How far the shading beside the edges would move the pose: each stretch's points moved back
// by the shift its surfaces' slopes predict (ShadingPeakShiftPx), the lines fitted again and
// the pose refined from `pose` with them; the change of (x, y, pan, tilt, swing), m and rad.
// A stretch whose side rows would reach another of the corner's edges, the image's border or
// a clipped surface is taken as unshifted. Zero where no edge has stretches.
Eigen::Matrix<double, 5, 1> PoseShiftFromShading(
    const cv::Mat& grey, const CameraIntrinsics& k, const CornerEdges& edges,
    const std::array<std::vector<EdgeStretch>, 3>& stretches,
    std::array<LineObservation, 3> observations, const CornerPose& pose,
    const std::array<int, 3>& axis_of_line, double point_sigma_px,
    const std::array<bool, 3>& wide_filter) {
  const double focal = 0.5 * (k.fx + k.fy);
  Eigen::Matrix<double, 5, 1> change = Eigen::Matrix<double, 5, 1>::Zero();
  bool any = false;
  for (int m = 0; m < 3; ++m) {
    if (stretches[m].empty()) continue;
    const double blur = edges.blur_sigma_px[m];
    const double filter =
        wide_filter[m] ? WeakViewEdgeDerivativeSigmaPx(blur) : EdgeDerivativeSigmaPx(blur);
    // The filtered peak's width (ShadingPeakShiftPx): the side rows start 3 of it (and 2 px)
    // out, where the step has risen fully, and take kShadingRowsPx of each surface.
    const double width =
        std::sqrt(blur * blur + (filter > 0 ? filter * filter : 5.0 / 6) + 1.0 / 6);
    const double inner = 3 * width + 2, outer = inner + kShadingRowsPx;
    std::vector<Eigen::Vector2d> moved = edges.points_px[m];
    for (const EdgeStretch& stretch : stretches[m]) {
      const Eigen::Vector2d normal(-stretch.along.y(), stretch.along.x());
      bool clear = true;
      for (int other = 0; other < 3 && clear; ++other) {
        if (other == m) continue;
        for (const auto& q : edges.points_px[other]) {
          const Eigen::Vector2d r = q - stretch.start_px;
          const double t = r.dot(stretch.along), o = r.dot(normal);
          if (t > -3 * width && t < stretch.length_px + 3 * width &&
              std::abs(o) < outer + 3 * width) {
            clear = false;
            break;
          }
        }
      }
      if (!clear) continue;
      const auto shading = MeasureShadingAcrossStretch(grey, stretch.start_px, stretch.along,
                                                       stretch.length_px, inner, outer);
      if (!shading) continue;
      const double shift = std::clamp(ShadingPeakShiftPx(*shading, blur, filter),
                                      -kMaxShadingShiftPx, kMaxShadingShiftPx);
      for (size_t i = stretch.first; i < stretch.end && i < moved.size(); ++i)
        moved[i] -= shift * normal;
    }
    std::vector<Eigen::Vector2d> points;
    std::vector<double> steps;
    Undistort(k, moved, edges.step_grey[m], &points, &steps);
    const auto fit = RobustLineFit(points, steps, kMinPointSigmaPx / focal);
    if (!fit) continue;
    LineObservation& obs = observations[m];
    const Eigen::Vector2d direction =
        fit->direction.dot(obs.direction) < 0 ? Eigen::Vector2d(-fit->direction) : fit->direction;
    double spread2 = 0, weights = 0;
    for (size_t i = 0; i < fit->inliers.size(); ++i) {
      spread2 +=
          fit->inlier_weights[i] * std::pow(direction.dot(fit->inliers[i] - fit->centroid), 2);
      weights += fit->inlier_weights[i];
    }
    obs.centroid = fit->centroid;
    obs.direction = direction;
    obs.spread = std::sqrt(spread2 / std::max(weights, 1e-9));
    any = true;
  }
  if (!any) return change;
  const auto moved_pose =
      RefineCornerPose(pose, observations, axis_of_line, focal, point_sigma_px, kLineBiasPx);
  if (!moved_pose) return change;
  const auto angle = [](double a, double b) { return std::remainder(a - b, 2 * std::numbers::pi); };
  change << moved_pose->pose.x_m - pose.x_m, moved_pose->pose.y_m - pose.y_m,
      angle(moved_pose->pose.pan_rad, pose.pan_rad),
      angle(moved_pose->pose.tilt_rad, pose.tilt_rad),
      angle(moved_pose->pose.swing_rad, pose.swing_rad);
  return change;
}

// One Y's three edges measured at full resolution and seen as lines (FitEdge, ObserveLine),
// with what the closed form and the pose fit need.
struct MeasuredLines {
  std::array<LineFit, 3> fits;
  std::array<std::vector<EdgeStretch>, 3> stretches;
  std::array<bool, 3> replaced{};  // the second pass's points replaced the detector's
  std::array<double, 3> spacing_px{};
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();  // normalized
  std::array<ObservedRay, 3> rays;
  std::array<LineObservation, 3> observations;
  double point_sigma_px = 0;
};

// `before`: the lines measured before, of which the edges not in `measure` are kept (their
// points in `edges` are then those lines'); nullptr measures all three.
Result<MeasuredLines> MeasureLines(const cv::Mat& grey, const CameraIntrinsics& k, double min_step,
                                   int spacing_px, const std::array<bool, 3>& wide_filter,
                                   const MeasuredLines* before, const std::array<bool, 3>& measure,
                                   CornerEdges* edges) {
  const double focal = 0.5 * (k.fx + k.fy);
  MeasuredLines out;
  for (int m = 0; m < 3; ++m) {
    if (before != nullptr && !measure[m]) {
      out.fits[m] = before->fits[m];
      out.stretches[m] = before->stretches[m];
      out.replaced[m] = before->replaced[m];
      continue;
    }
    auto fit = FitEdge(grey, k, m, min_step, spacing_px, wide_filter[m],
                       before != nullptr ? &before->fits[m] : nullptr, edges, &out.replaced[m],
                       &out.stretches[m]);
    if (!fit) return MakeError(ErrorCode::kNotFound, "a corner edge could not be fitted");
    if (before != nullptr && !out.replaced[m])
      return MakeError(ErrorCode::kNotFound, "an edge measured again gave too few points");
    out.fits[m] = std::move(*fit);
  }
  const auto corner = ConstrainedCorner(out.fits);
  if (!corner) return MakeError(ErrorCode::kDegenerate, "the corner edges are parallel");
  out.corner = *corner;
  // The second pass (2 px apart) replaces an edge's first points when it finds enough.
  for (int m = 0; m < 3; ++m)
    out.spacing_px[m] = out.replaced[m] ? spacing_px : edges->sample_spacing_px;
  double point_sigma2 = 0;
  int total_points = 0;
  for (int m = 0; m < 3; ++m) {
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : out.fits[m].inliers) scatter += (p - *corner) * (p - *corner).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    Eigen::Vector2d d = eig.eigenvectors().col(1);
    if (d.dot(out.fits[m].centroid - *corner) < 0) d = -d;
    out.rays[m] = {*corner, d};
    out.observations[m] = ObserveLine(out.fits[m], *corner, out.spacing_px[m], focal);
    point_sigma2 += std::pow(out.fits[m].normal_rms * focal, 2) * out.observations[m].num_points;
    total_points += out.observations[m].num_points;
  }
  out.point_sigma_px =
      std::max(std::sqrt(point_sigma2 / std::max(total_points, 1)), kMinPointSigmaPx);
  return out;
}

// A weakly determined view: its blurred edges are measured again along the refined lines,
// with the wider filter whose larger shading bias the shading correction removes
// (CornerQualityOptions::remeasure_above_relative_sigma; never where the shading is not
// read). Not a Y rolled past max_swing: that one gives way to the next Y anyway
// (LocateCorner). Where the second measurement refines, it replaces the first.
void MeasureWeakViewAgain(const cv::Mat& grey, const CameraIntrinsics& k, double min_step,
                          int spacing_px, const CornerQualityOptions& quality,
                          const std::array<int, 3>& axis_of_line, CornerEdges* edges,
                          Result<MeasuredLines>* lines, Result<CornerRefinement>* refined,
                          std::array<bool, 3>* wide_filter) {
  const double focal = 0.5 * (k.fx + k.fy);
  const double first_variance = (*refined)->covariance(0, 0) + (*refined)->covariance(1, 1);
  const double first_horizontal_m = std::hypot((*refined)->pose.x_m, (*refined)->pose.y_m);
  if (std::sqrt(first_variance) > quality.remeasure_above_relative_sigma * first_horizontal_m &&
      std::sqrt(first_variance) > quality.shading_check_above_relative_sigma * first_horizontal_m &&
      std::abs((*refined)->pose.swing_rad) <= quality.max_swing_rad) {
    std::array<bool, 3> measure{};
    for (int m = 0; m < 3; ++m)
      measure[m] = WeakViewEdgeDerivativeSigmaPx(edges->blur_sigma_px[m]) > 0;
    if (measure[0] || measure[1] || measure[2]) {
      CornerEdges again = *edges;
      auto wide = MeasureLines(grey, k, min_step, spacing_px, measure, &**lines, measure, &again);
      auto wide_refined = wide
                              ? RefineCornerPose((*refined)->pose, wide->observations, axis_of_line,
                                                 focal, wide->point_sigma_px, kLineBiasPx)
                              : Result<CornerRefinement>(wide.error());
      if (wide_refined) {
        *lines = std::move(wide);
        *refined = std::move(wide_refined);
        *edges = std::move(again);
        *wide_filter = measure;
      }
    }
  }
}

// The edges listed as X, Y, Z (the tracker relies on it), from the detector's order.
CornerEdges OrderedByAxis(CornerEdges edges, const std::array<int, 3>& axis_of_line) {
  CornerEdges ordered = edges;
  for (int m = 0; m < 3; ++m) {
    const int axis = axis_of_line[m];
    ordered.direction[axis] = edges.direction[m];
    ordered.points_px[axis] = std::move(edges.points_px[m]);
    ordered.step_grey[axis] = std::move(edges.step_grey[m]);
    ordered.polarity[axis] = edges.polarity[m];
    ordered.blur_sigma_px[axis] = edges.blur_sigma_px[m];
  }
  return ordered;
}

}  // namespace

const char* ToString(CornerSource source) {
  return source == CornerSource::kTracked ? "tracked" : "detected";
}

std::ostream& operator<<(std::ostream& os, CornerSource source) { return os << ToString(source); }

std::ostream& operator<<(std::ostream& os, const CornerLocation& c) {
  os << "CornerLocation{" << c.pose << " sigma=(" << c.Sigma().transpose() << ") corner_px=("
     << c.corner_px.transpose() << ") rms=" << c.rms_px << " px " << ToString(c.source);
  if (c.suspect) os << " SUSPECT: " << c.suspect_reason;
  return os << "}";
}

Result<CornerLocation> LocateCornerFromEdges(const cv::Mat& grey, const CameraIntrinsics& k,
                                             double zc, CornerEdges edges,
                                             const CornerDetectorOptions& options,
                                             const CornerQualityOptions& quality,
                                             const CornerPose* previous) {
  const double focal = 0.5 * (k.fx + k.fy);
  const double min_step = MinStepGrey(options, edges.noise_sigma_grey);
  std::array<bool, 3> wide_filter{};
  auto lines =
      MeasureLines(grey, k, min_step, options.measure_spacing_px, wide_filter, nullptr, {}, &edges);
  if (!lines) return lines.error();

  CornerPose initial;
  std::array<int, 3> axis_of_line{0, 1, 2};
  if (previous != nullptr) {
    initial = *previous;
    initial.z_m = zc;
  } else {
    const auto closed = SolveCornerClosedForm(lines->rays, zc);
    if (!closed) return closed.error();
    initial = closed->pose;
    axis_of_line = closed->axis_of_ray;
  }
  auto refined = RefineCornerPose(initial, lines->observations, axis_of_line, focal,
                                  lines->point_sigma_px, kLineBiasPx);
  if (!refined) return refined.error();
  MeasureWeakViewAgain(grey, k, min_step, options.measure_spacing_px, quality, axis_of_line, &edges,
                       &lines, &refined, &wide_filter);
  const auto& fits = lines->fits;
  const auto& spacing_px = lines->spacing_px;
  const Eigen::Vector2d corner = lines->corner;
  const double point_sigma_px = lines->point_sigma_px;

  CornerLocation out;
  out.pose = refined->pose;
  out.covariance = refined->covariance;
  out.noise_sigma_grey = edges.measurement_noise_grey;
  out.edges_measured_again = wide_filter[0] || wide_filter[1] || wide_filter[2];
  // A one-sided shading slope beside a faint edge moves its every point the same way, which
  // neither the points' scatter nor the lines' agreement shows
  // (tests/accuracy/corner_pose_notes.md, "Shading"). Where the pose is imprecise enough for that
  // to matter, the shift the shading predicts is removed, and counted in the covariance too: each
  // stretch's slopes are read from noisy pixels, so where there was no bias the shift is the
  // correction's own noise, and where there was one it is larger (client/cli/GUIDE.md, "The shading
  // beside a faint edge"). (Edges measured with the wider filter always: their bias is larger.)
  const double horizontal_m = std::hypot(out.pose.x_m, out.pose.y_m);
  if (wide_filter[0] || wide_filter[1] || wide_filter[2] ||
      std::sqrt(out.covariance(0, 0) + out.covariance(1, 1)) >
          quality.shading_check_above_relative_sigma * horizontal_m) {
    const Eigen::Matrix<double, 5, 1> shading_shift =
        PoseShiftFromShading(grey, k, edges, lines->stretches, lines->observations, out.pose,
                             axis_of_line, point_sigma_px, wide_filter);
    out.pose = Canonical(MovedBy(out.pose, shading_shift));
    out.covariance += shading_shift * shading_shift.transpose();
    out.shading_shift = shading_shift;
  }
  const Eigen::Matrix3d r = RotationCameraFromCorner(out.pose);
  out.q_corner_camera = Eigen::Quaterniond(r.transpose()).normalized();
  const Eigen::Vector3d c_cam = CornerToCamera(out.pose, Eigen::Vector3d::Zero());
  if (c_cam.z() <= 0) {
    return MakeError(ErrorCode::kDegenerate, "the refined pose puts the corner behind the camera");
  }
  out.corner_px = NormalizedToPixel(k, c_cam.head<2>() / c_cam.z());
  const auto& parts = refined->horizontal_variance_m2_by_line;
  const double horizontal_variance = parts[0] + parts[1] + parts[2];
  for (int m = 0; m < 3; ++m)
    out.support[axis_of_line[m]].position_variance_share =
        horizontal_variance > 0 ? parts[m] / horizontal_variance : 0;
  AssessSupport(grey, k, fits, axis_of_line, corner, quality, spacing_px, &out);
  out.edges = OrderedByAxis(std::move(edges), axis_of_line);
  return out;
}

Result<CornerLocation> LocateCorner(const cv::Mat& grey, const CameraIntrinsics& k, double zc,
                                    const CornerDetectorOptions& options,
                                    const CornerQualityOptions& quality) {
  if (!(zc > 0)) {
    return MakeError(
        ErrorCode::kInvalidArgument,
        "the camera-to-ceiling distance is not set: give --ceiling-distance or corner { "
        "ceiling_distance } in the calibration file");
  }
  if (grey.cols != k.width_px || grey.rows != k.height_px) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "image is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         " but the calibration is for " + std::to_string(k.width_px) + "x" +
                         std::to_string(k.height_px));
  }
  // The best supported Y first; one the pose rejects (not a corner seen from inside a room)
  // gives way to the next. So does one whose edges or mount say it is not the ceiling's Y
  // (suspect for more than imprecision: the camera would be rolled past max_swing, the
  // edges' steps do not add up, a stronger edge leaves the corner), to the next Y whose pose
  // raises no such doubt, at a quarter of the resolution and then at half. Far views that
  // look almost level see the floor's corner below the ceiling's, and the floor's was taken
  // first, its pose far off and flagged as a camera rolled over (tests/accuracy/
  // corner_pose_notes.md, "Wrong Ys"). Where every Y is doubted, the first the finer resolution
  // found stands, flagged: the coarse image may favour a wrong Y (clutter beside a faint edge), and
  // a map would take the pose as its next prior. A pose flagged only as imprecise is taken: its
  // edges agree with it and with each other, and they are measured at full resolution whichever
  // resolution found them.
  std::optional<CornerLocation> located, doubted;
  std::optional<Error> pose_error;
  const auto detect_error = ForEachCornerCandidate(grey, options, &k, [&](CornerEdges edges) {
    auto r = LocateCornerFromEdges(grey, k, zc, std::move(edges), options, quality);
    if (!r) {
      if (!pose_error) pose_error = r.error();
      return false;
    }
    if (r->suspect && !r->suspect_only_imprecise) {
      if (!doubted || r->edges.detection_scale > doubted->edges.detection_scale)
        doubted = std::move(*r);
      return false;
    }
    located = std::move(*r);
    return true;
  });
  if (located) return std::move(*located);
  if (doubted) return std::move(*doubted);
  if (pose_error) return *pose_error;
  return *detect_error;
}

}  // namespace monocle
