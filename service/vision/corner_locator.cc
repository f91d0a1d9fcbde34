#include "service/vision/corner_locator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

namespace monocle {
namespace {

struct LineFit {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero(), direction = Eigen::Vector2d::UnitX();
  std::vector<Eigen::Vector2d> inliers;  // normalized coordinates
  double normal_rms = 0;                 // normalized units
};

// Total least squares (the paper's eq. 17) with iterative rejection of points further than
// 3 robust sigmas: clutter crossing the edge, or the edge ending.
std::optional<LineFit> RobustLineFit(std::vector<Eigen::Vector2d> pts, double floor_sigma) {
  LineFit fit;
  for (int iteration = 0; iteration < 4; ++iteration) {
    if (pts.size() < 5) return std::nullopt;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : pts) mean += p;
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : pts) scatter += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    fit.centroid = mean;
    fit.direction = eig.eigenvectors().col(1);
    const Eigen::Vector2d normal = eig.eigenvectors().col(0);
    std::vector<double> dist;
    for (const auto& p : pts) dist.push_back(std::abs(normal.dot(p - mean)));
    std::vector<double> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double sigma = std::max(1.4826 * sorted[sorted.size() / 2], floor_sigma);
    std::vector<Eigen::Vector2d> kept;
    double sum2 = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (dist[i] <= 3 * sigma) {
        kept.push_back(pts[i]);
        sum2 += dist[i] * dist[i];
      }
    }
    fit.normal_rms = std::sqrt(sum2 / std::max<size_t>(kept.size(), 1));
    const bool converged = kept.size() == pts.size();
    pts = std::move(kept);
    if (converged) break;
  }
  fit.inliers = std::move(pts);
  return fit;
}

std::optional<Eigen::Vector2d> IntersectLines(const LineFit& a, const LineFit& b) {
  Eigen::Matrix2d m;
  m << a.direction, -b.direction;
  if (std::abs(m.determinant()) < 1e-9) return std::nullopt;
  const Eigen::Vector2d t = m.inverse() * (b.centroid - a.centroid);
  return a.centroid + t.x() * a.direction;
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const CornerLocation& c) {
  return os << "CornerLocation{" << c.pose << " sigma=(" << c.Sigma().transpose() << ") corner_px=("
            << c.corner_px.transpose() << ") rms=" << c.rms_px << " px}";
}

Result<CornerLocation> LocateCorner(const cv::Mat& grey, const CameraIntrinsics& k, double zc,
                                    const CornerDetectorOptions& options) {
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
  auto edges = DetectCornerEdges(grey, options, &k);
  if (!edges) return edges.error();
  const double focal = 0.5 * (k.fx + k.fy);
  const double floor_sigma = 0.05 / focal;  // no edge is measured better than 0.05 px

  auto undistort = [&](const std::vector<Eigen::Vector2d>& px) {
    std::vector<Eigen::Vector2d> out;
    for (const auto& p : px) {
      if (const auto n = PixelToNormalized(k, p)) out.push_back(*n);
    }
    return out;
  };

  std::array<LineFit, 3> fits;
  for (int m = 0; m < 3; ++m) {
    auto first = RobustLineFit(undistort(edges->points_px[m]), floor_sigma);
    if (!first) return MakeError(ErrorCode::kNotFound, "a corner edge could not be fitted");
    // Second pass along the fitted line as the lens bends it, with a narrower window: the
    // straight first pass drifts off a distorted edge far from the corner.
    const Eigen::Vector2d corner_n =
        PixelToNormalized(k, edges->corner_px).value_or(first->centroid);
    Eigen::Vector2d dir = first->direction;
    if (dir.dot(first->centroid - corner_n) < 0) dir = -dir;
    const Eigen::Vector2d start = first->centroid + dir * dir.dot(corner_n - first->centroid);
    std::vector<Eigen::Vector2d> positions, normals;
    const double step = 2.0 / focal;
    for (double t = 8.0 / focal; t < 4.0; t += step) {
      Eigen::Matrix2d j;
      const Eigen::Vector2d px = NormalizedToPixel(k, start + t * dir, &j);
      if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1) break;
      const Eigen::Vector2d along = (j * dir).normalized();
      positions.push_back(px);
      normals.emplace_back(-along.y(), along.x());
    }
    // Keep the detector's polarity convention: its normal is the left normal of its ray.
    const Eigen::Vector2d detector_normal(-edges->direction[m].y(), edges->direction[m].x());
    const int polarity = normals.empty() || normals[0].dot(detector_normal) > 0
                             ? edges->polarity[m]
                             : -edges->polarity[m];
    auto second = MeasureEdgePoints(grey, positions, normals, 2.5, polarity, options.min_step_grey);
    if (second.size() >= 10) edges->points_px[m] = std::move(second);
    auto refit = RobustLineFit(undistort(edges->points_px[m]), floor_sigma);
    if (!refit) return MakeError(ErrorCode::kNotFound, "a corner edge could not be fitted");
    if (refit->direction.dot(refit->centroid - corner_n) < 0) refit->direction = -refit->direction;
    fits[m] = *refit;
  }

  // Section 3.5: the corner is the centre of the three pairwise intersections; each line is
  // refitted through it. Each intersection is weighted by sin^2 of its lines' angle: a Y
  // often has two nearly collinear edges whose intersection slides along them; with well
  // separated lines this is the paper's plain centre.
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();
  double weights = 0;
  for (int m = 0; m < 3; ++m) {
    const auto p = IntersectLines(fits[m], fits[(m + 1) % 3]);
    if (!p) continue;
    const double sine = fits[m].direction.x() * fits[(m + 1) % 3].direction.y() -
                        fits[m].direction.y() * fits[(m + 1) % 3].direction.x();
    corner += sine * sine * *p;
    weights += sine * sine;
  }
  if (!(weights > 1e-6)) return MakeError(ErrorCode::kDegenerate, "the corner edges are parallel");
  corner /= weights;
  std::array<ObservedRay, 3> rays;
  std::array<LineObservation, 3> observations;
  double point_sigma2 = 0;
  int total_points = 0;
  for (int m = 0; m < 3; ++m) {
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : fits[m].inliers) scatter += (p - corner) * (p - corner).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    Eigen::Vector2d d = eig.eigenvectors().col(1);
    if (d.dot(fits[m].centroid - corner) < 0) d = -d;
    rays[m] = {corner, d};
    auto& obs = observations[m];
    obs.centroid = fits[m].centroid;
    obs.direction = fits[m].direction;
    obs.num_points = static_cast<int>(fits[m].inliers.size());
    double spread2 = 0;
    for (const auto& p : fits[m].inliers)
      spread2 += std::pow(obs.direction.dot(p - obs.centroid), 2);
    obs.spread = std::sqrt(spread2 / std::max(obs.num_points, 1));
    point_sigma2 += std::pow(fits[m].normal_rms * focal, 2) * obs.num_points;
    total_points += obs.num_points;
  }
  const double point_sigma_px = std::sqrt(point_sigma2 / std::max(total_points, 1));

  const auto closed = SolveCornerClosedForm(rays, zc);
  if (!closed) return closed.error();
  const auto refined = RefineCornerPose(closed->pose, observations, closed->axis_of_ray, focal,
                                        std::max(point_sigma_px, 0.05));
  if (!refined) return refined.error();

  CornerLocation out;
  out.pose = refined->pose;
  out.covariance = refined->covariance;
  const Eigen::Matrix3d r = RotationCameraFromCorner(out.pose);
  out.q_corner_camera = Eigen::Quaterniond(r.transpose()).normalized();
  const Eigen::Vector3d c_cam = CornerToCamera(out.pose, Eigen::Vector3d::Zero());
  out.corner_px = NormalizedToPixel(k, c_cam.head<2>() / c_cam.z());
  // RMS distance of every inlier to the line the refined pose predicts for its axis.
  double sum2 = 0;
  for (int m = 0; m < 3; ++m) {
    const int axis = closed->axis_of_ray[m];
    const Eigen::Vector3d a = CornerToCamera(
        out.pose, 1e-3 * CameraPosition(out.pose).norm() * Eigen::Vector3d::Unit(axis));
    const Eigen::Vector2d c2 = c_cam.head<2>() / c_cam.z();
    const Eigen::Vector2d dir = (a.head<2>() / a.z() - c2).normalized();
    const Eigen::Vector2d normal(-dir.y(), dir.x());
    for (const auto& p : fits[m].inliers) sum2 += std::pow(normal.dot(p - c2) * focal, 2);
    // Far end: the inlier furthest from the corner, back in pixels.
    Eigen::Vector2d far = fits[m].inliers.front();
    for (const auto& p : fits[m].inliers) {
      if ((p - corner).squaredNorm() > (far - corner).squaredNorm()) far = p;
    }
    out.line_end_px[axis] = NormalizedToPixel(k, far);
    out.points_per_line[axis] = static_cast<int>(fits[m].inliers.size());
  }
  out.rms_px = std::sqrt(sum2 / std::max(total_points, 1));
  out.edges = std::move(*edges);
  return out;
}

}  // namespace monocle
