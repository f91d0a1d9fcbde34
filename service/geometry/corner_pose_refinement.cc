#include "service/geometry/corner_pose_refinement.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "service/geometry/levenberg_marquardt.h"

namespace monocle {

namespace {

// The covariance of the six residuals (two per line), pixels^2 times the weights': each
// line's own scatter, its direction's extra uncertainty, and a whole-line offset of
// `line_bias_px` (1 sigma) shared by its two residuals.
Eigen::Matrix<double, 6, 6> ResidualCovariance(const std::array<LineObservation, 3>& lines,
                                               double point_sigma_px, double line_bias_px) {
  // Residual pair k has variance point_sigma_px^2 when line k's points scatter as its weight
  // assumes (point_sigma_px times its relative sigma); scaled by how they actually scatter.
  // Residual pair k: the two ends (centroid -+ spread) of line k. Their half sum is the
  // line's offset, their half difference its direction times the spread; independent ends
  // give both half the variance. A direction less certain than that (direction_sigma_scale)
  // adds to the difference only.
  Eigen::Matrix<double, 6, 6> residual_covariance = Eigen::Matrix<double, 6, 6>::Zero();
  for (int k = 0; k < 3; ++k) {
    const double assumed =
        point_sigma_px *
        (lines[k].point_sigma_px > 0 ? lines[k].point_sigma_px / point_sigma_px : 1.0);
    const double actual = lines[k].scatter_sigma_px > 0 ? lines[k].scatter_sigma_px : assumed;
    const double direction_scale = std::max(lines[k].direction_sigma_scale, 1.0);
    const double end_variance = std::pow(point_sigma_px * actual / assumed, 2);
    const double offset_part = 0.5 * end_variance;
    const double direction_part = 0.5 * end_variance * direction_scale * direction_scale;
    residual_covariance.block<2, 2>(2 * k, 2 * k) << offset_part + direction_part,
        offset_part - direction_part, offset_part - direction_part, offset_part + direction_part;
  }
  if (line_bias_px > 0) {
    // Residual k's scale: weight_k * (offset in normalized units); a line offset by b pixels
    // moves both of its residuals by weight_k * b / focal, fully correlated.
    for (int k = 0; k < 3; ++k) {
      const double n = lines[k].independent_points > 0 ? lines[k].independent_points
                                                       : std::max(lines[k].num_points, 1);
      const double sigma =
          lines[k].point_sigma_px > 0 ? lines[k].point_sigma_px / point_sigma_px : 1.0;
      const double weight = std::sqrt(std::max(n, 1.0) / 2.0) / sigma;  // focal cancels
      residual_covariance.block<2, 2>(2 * k, 2 * k).array() += std::pow(weight * line_bias_px, 2);
    }
  }
  return residual_covariance;
}

}  // namespace

std::optional<Eigen::Matrix<double, 6, 1>> CornerLineResiduals(
    const CornerPose& pose, const std::array<LineObservation, 3>& lines,
    const std::array<int, 3>& axis_of_line, double focal_px, double point_sigma_px) {
  const Eigen::Matrix3d rot = RotationCameraFromCorner(pose);
  const Eigen::Vector3d c = CameraPosition(pose);
  Eigen::Matrix<double, 6, 1> r;
  for (int k = 0; k < 3; ++k) {
    const auto img = ImageOfAxis(rot, c, axis_of_line[k]);
    if (!img) return std::nullopt;
    const Eigen::Vector2d normal(-img->direction.y(), img->direction.x());
    // Two points with the same mean and spread along the line as the edge points: their
    // squared distances to a line sum to the points' own, up to a constant.
    // Weighted by each line's own noise and independent points (relative to point_sigma_px).
    const double n = lines[k].independent_points > 0 ? lines[k].independent_points
                                                     : std::max(lines[k].num_points, 1);
    const double sigma =
        lines[k].point_sigma_px > 0 ? lines[k].point_sigma_px / point_sigma_px : 1.0;
    const double weight = std::sqrt(std::max(n, 1.0) / 2.0) * focal_px / sigma;
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector2d p =
          lines[k].centroid + (side ? 1.0 : -1.0) * lines[k].spread * lines[k].direction;
      r[2 * k + side] = weight * normal.dot(p - img->corner);
    }
  }
  return r;
}

Result<CornerRefinement> RefineCornerPose(const CornerPose& initial,
                                          const std::array<LineObservation, 3>& lines,
                                          const std::array<int, 3>& axis_of_line, double focal_px,
                                          double point_sigma_px, double line_bias_px) {
  const double zc = initial.z_m;
  auto residuals = [&](const Eigen::Matrix<double, 5, 1>& q, Eigen::Matrix<double, 6, 1>* r) {
    const auto line_residuals = CornerLineResiduals(CornerPose{q[0], q[1], zc, q[2], q[3], q[4]},
                                                    lines, axis_of_line, focal_px, point_sigma_px);
    if (!line_residuals) return false;
    *r = *line_residuals;
    return true;
  };
  Eigen::Matrix<double, 5, 1> q;
  q << initial.x_m, initial.y_m, initial.pan_rad, initial.tilt_rad, initial.swing_rad;
  const auto summary = MinimizeLevenbergMarquardtOf<6, 5>(
      residuals, 6, &q, {.forward_differences_while_iterating = true});
  if (!summary.started || !summary.has_jacobian) {
    return MakeError(ErrorCode::kDegenerate, "the corner pose refinement failed");
  }
  const Eigen::Matrix<double, 5, 5> jtj = summary.jacobian.transpose() * summary.jacobian;
  Eigen::FullPivLU<Eigen::Matrix<double, 5, 5>> lu(jtj);
  if (!lu.isInvertible()) {
    return MakeError(ErrorCode::kDegenerate,
                     "the corner lines do not determine the pose (degenerate view)");
  }
  CornerRefinement out;
  out.pose = Canonical(CornerPose{q[0], q[1], zc, q[2], q[3], q[4]});
  const Eigen::Matrix<double, 5, 5> jtj_inverse = lu.inverse();
  const Eigen::Matrix<double, 6, 6> residual_covariance =
      ResidualCovariance(lines, point_sigma_px, line_bias_px);
  const Eigen::Matrix<double, 5, 6> gain = jtj_inverse * summary.jacobian.transpose();
  // Where every line scatters as its weight assumes, the residuals' covariance is
  // point_sigma_px^2 I and this is point_sigma_px^2 (J^T J)^-1. Written as G D G^T, it is a
  // sum over the lines (D is block diagonal): each line's part is its own.
  out.covariance = gain * residual_covariance * gain.transpose();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix<double, 2, 2> line_gain = gain.block<2, 2>(0, 2 * k);
    out.horizontal_variance_m2_by_line[k] =
        (line_gain * residual_covariance.block<2, 2>(2 * k, 2 * k) * line_gain.transpose()).trace();
  }
  // G D G^T is symmetric up to rounding, which differs between its two triangles.
  out.covariance = (0.5 * (out.covariance + out.covariance.transpose())).eval();
  int total = 0;
  for (const auto& l : lines) total += std::max(l.num_points, 1);
  // RMS of the unweighted line residuals (the weights above only shape the covariance).
  double sum2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double n = lines[k].independent_points > 0 ? lines[k].independent_points
                                                     : std::max(lines[k].num_points, 1);
    const double sigma =
        lines[k].point_sigma_px > 0 ? lines[k].point_sigma_px / point_sigma_px : 1.0;
    const double scale = std::max(lines[k].num_points, 1) / std::max(n, 1.0) * sigma * sigma;
    sum2 += scale * (summary.residuals.segment<2>(2 * k).squaredNorm());
  }
  out.rms_px = std::sqrt(sum2 / total);
  return out;
}

}  // namespace monocle
