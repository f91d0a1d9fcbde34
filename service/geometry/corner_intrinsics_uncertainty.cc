#include "service/geometry/corner_intrinsics_uncertainty.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

#include "service/geometry/corner_pose_refinement.h"

namespace monocle {
namespace {

// Enough points to give each edge's centroid and direction; more only cost time.
constexpr size_t kMaxPointsPerEdge = 32;

// An edge's points as rays of the intrinsics `k`, each with how it moves when they change.
struct EdgeRays {
  std::vector<Eigen::Vector2d> normalized;
  std::vector<Eigen::Matrix<double, 2, kNumIntrinsicParams>> d_normalized;
  int fitted_points = 0;
};

EdgeRays RaysOf(const CameraIntrinsics& k, const std::vector<Eigen::Vector2d>& points_px,
                int fitted_points) {
  EdgeRays rays;
  rays.fitted_points = fitted_points;
  const size_t stride = std::max<size_t>(1, points_px.size() / kMaxPointsPerEdge);
  for (size_t i = 0; i < points_px.size(); i += stride) {
    Eigen::Matrix2d normalized_from_pixel;
    const auto p = PixelToNormalized(k, points_px[i], &normalized_from_pixel);
    if (!p) continue;
    rays.normalized.push_back(*p);
    rays.d_normalized.push_back(NormalizedJacobianWrtIntrinsics(k, *p, normalized_from_pixel));
  }
  return rays;
}

// The edge's observation (centroid, principal direction away from `corner`, spread) with
// every ray moved by `change` of the intrinsics.
LineObservation ObserveEdge(const EdgeRays& rays, const IntrinsicParams& change,
                            const Eigen::Vector2d& corner) {
  std::vector<Eigen::Vector2d> points(rays.normalized.size());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    points[i] = rays.normalized[i] + rays.d_normalized[i] * change;
    centroid += points[i];
  }
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) scatter += (p - centroid) * (p - centroid).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  Eigen::Vector2d direction = eig.eigenvectors().col(1);
  if (direction.dot(centroid - corner) < 0) direction = -direction;
  LineObservation obs;
  obs.centroid = centroid;
  obs.direction = direction;
  obs.spread = std::sqrt(eig.eigenvalues()(1) / static_cast<double>(points.size()));
  obs.num_points = std::max(rays.fitted_points, static_cast<int>(points.size()));
  return obs;
}

std::array<LineObservation, 3> Observe(const std::array<EdgeRays, 3>& edges,
                                       const IntrinsicParams& change,
                                       const Eigen::Vector2d& corner) {
  return {ObserveEdge(edges[0], change, corner), ObserveEdge(edges[1], change, corner),
          ObserveEdge(edges[2], change, corner)};
}

}  // namespace

Eigen::Matrix<double, 5, kNumIntrinsicParams> CornerPoseJacobianWrtIntrinsics(
    const CameraIntrinsics& k, const CornerPose& pose, const CornerEdgePixels& edges,
    const IntrinsicParams& step) {
  using Jacobian = Eigen::Matrix<double, 5, kNumIntrinsicParams>;
  const Eigen::Vector3d corner_in_camera = CornerToCamera(pose, Eigen::Vector3d::Zero());
  if (corner_in_camera.z() <= 0) return Jacobian::Zero();
  const Eigen::Vector2d corner = corner_in_camera.head<2>() / corner_in_camera.z();
  std::array<EdgeRays, 3> rays;
  for (int axis = 0; axis < 3; ++axis) {
    rays[axis] = RaysOf(k, edges.points_px[axis], edges.fitted_points[axis]);
    if (rays[axis].normalized.size() < 2) return Jacobian::Zero();
  }
  const double focal = 0.5 * (k.fx + k.fy);
  const auto residuals = [&](const CornerPose& p, const std::array<LineObservation, 3>& lines) {
    return CornerLineResiduals(p, lines, {0, 1, 2}, focal, 1.0);
  };
  // At the fit's optimum, a change dr of the residuals moves the pose by -(J^T J)^-1 J^T dr
  // (to first order), J the residuals' Jacobian in the pose.
  const auto unchanged = Observe(rays, IntrinsicParams::Zero(), corner);
  Eigen::Matrix<double, 6, 5> d_residual_d_pose;
  const double pose_step[5] = {1e-6, 1e-6, 1e-7, 1e-7, 1e-7};
  for (int i = 0; i < 5; ++i) {
    Eigen::Matrix<double, 5, 1> q = Eigen::Matrix<double, 5, 1>::Zero();
    q[i] = pose_step[i];
    const auto plus = residuals(MovedBy(pose, q), unchanged);
    const auto minus = residuals(MovedBy(pose, -q), unchanged);
    if (!plus || !minus) return Jacobian::Zero();
    d_residual_d_pose.col(i) = (*plus - *minus) / (2 * pose_step[i]);
  }
  Eigen::Matrix<double, 6, kNumIntrinsicParams> d_residual_d_k =
      Eigen::Matrix<double, 6, kNumIntrinsicParams>::Zero();
  for (int j = 0; j < kNumIntrinsicParams; ++j) {
    if (!(step[j] > 0)) continue;
    IntrinsicParams delta = IntrinsicParams::Zero();
    delta[j] = step[j];
    const auto plus = residuals(pose, Observe(rays, delta, corner));
    const auto minus = residuals(pose, Observe(rays, -delta, corner));
    if (!plus || !minus) return Jacobian::Zero();
    d_residual_d_k.col(j) = (*plus - *minus) / (2 * step[j]);
  }
  const Eigen::Matrix<double, 5, 5> normal = d_residual_d_pose.transpose() * d_residual_d_pose;
  return -normal.ldlt().solve(d_residual_d_pose.transpose() * d_residual_d_k);
}

Eigen::Matrix<double, 5, 5> CornerPoseCovarianceFromIntrinsics(const CameraIntrinsics& k,
                                                               const CornerPose& pose,
                                                               const CornerEdgePixels& edges,
                                                               const IntrinsicsCovariance& c) {
  const IntrinsicParams step = c.diagonal().cwiseMax(0).cwiseSqrt();
  if (step.isZero()) return Eigen::Matrix<double, 5, 5>::Zero();
  const auto jacobian = CornerPoseJacobianWrtIntrinsics(k, pose, edges, step);
  const Eigen::Matrix<double, 5, 5> added = jacobian * c * jacobian.transpose();
  return 0.5 * (added + added.transpose());
}

}  // namespace monocle
