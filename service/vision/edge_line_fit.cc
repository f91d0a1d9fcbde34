#include "service/vision/edge_line_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace monocle {

double BeyondGapLeverage(const LineFit& fit, const Eigen::Vector2d& corner, double focal,
                         double max_gap_px) {
  std::vector<double> along;
  for (const auto& p : fit.inliers) along.push_back(fit.direction.dot(p - corner) * focal);
  std::sort(along.begin(), along.end());
  size_t contiguous = along.empty() ? 0 : 1;
  while (contiguous < along.size() && along[contiguous] - along[contiguous - 1] <= max_gap_px)
    ++contiguous;
  auto information = [&](size_t n) {
    double mean = 0, spread2 = 0;
    for (size_t i = 0; i < n; ++i) mean += along[i] / n;
    for (size_t i = 0; i < n; ++i) spread2 += (along[i] - mean) * (along[i] - mean);
    return std::sqrt(spread2);  // sqrt(n) * spread
  };
  if (contiguous < 5 || contiguous == along.size()) return 1;
  return std::max(1.0, information(along.size()) / std::max(information(contiguous), 1e-9));
}

std::optional<LineFit> RobustLineFit(std::vector<Eigen::Vector2d> pts, std::vector<double> steps,
                                     double floor_sigma) {
  LineFit fit;
  // Scratch reused across the iterations (and calls): this fit runs six times a frame.
  thread_local std::vector<double> w, step2, sorted, dist;
  for (int iteration = 0; iteration < 4; ++iteration) {
    if (pts.size() < 5) return std::nullopt;
    const size_t n = pts.size();
    step2.resize(n);
    for (size_t i = 0; i < n; ++i) step2[i] = steps[i] * steps[i];
    sorted.assign(step2.begin(), step2.end());
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    const double median_step2 = std::max(sorted[n / 2], 1e-6);
    w.resize(n);
    for (size_t i = 0; i < n; ++i) w[i] = std::clamp(step2[i] / median_step2, 0.25, 4.0);
    double wsum = 0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < n; ++i) mean += w[i] * pts[i], wsum += w[i];
    mean /= wsum;
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (size_t i = 0; i < n; ++i) scatter += w[i] * (pts[i] - mean) * (pts[i] - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    fit.centroid = mean;
    fit.direction = eig.eigenvectors().col(1);
    const Eigen::Vector2d normal = eig.eigenvectors().col(0);
    dist.resize(n);
    for (size_t i = 0; i < n; ++i) dist[i] = std::abs(normal.dot(pts[i] - mean)) * std::sqrt(w[i]);
    sorted.assign(dist.begin(), dist.end());
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    const double sigma = std::max(1.4826 * sorted[n / 2], floor_sigma);
    // Keep the points within 3 sigma, in place and in order.
    fit.inlier_weights.clear();
    size_t kept = 0;
    double sum2 = 0, kept_wsum = 0;
    for (size_t i = 0; i < n; ++i) {
      if (dist[i] <= 3 * sigma) {
        pts[kept] = pts[i];
        steps[kept] = steps[i];
        ++kept;
        fit.inlier_weights.push_back(w[i]);
        sum2 += dist[i] * dist[i];
        kept_wsum += w[i];
      }
    }
    // The weighted RMS: the scatter of equally weighted points that would fix the line as
    // well (the covariance treats the points as equal; see LineObservation's spread).
    fit.normal_rms = std::sqrt(sum2 / std::max(kept_wsum, 1e-9));
    pts.resize(kept);
    steps.resize(kept);
    if (kept == n) break;
  }
  fit.inliers = std::move(pts);
  fit.inlier_steps = std::move(steps);
  return fit;
}

double MaxGapPx(double spacing_px) { return std::max(40.0, 8 * spacing_px); }

std::optional<Eigen::Vector2d> IntersectLines(const LineFit& a, const LineFit& b) {
  Eigen::Matrix2d m;
  m << a.direction, -b.direction;
  if (std::abs(m.determinant()) < 1e-9) return std::nullopt;
  const Eigen::Vector2d t = m.inverse() * (b.centroid - a.centroid);
  return a.centroid + t.x() * a.direction;
}

std::optional<Eigen::Vector2d> ConstrainedCorner(const std::array<LineFit, 3>& fits) {
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
  if (!(weights > 1e-6)) return std::nullopt;
  return corner / weights;
}

}  // namespace monocle
