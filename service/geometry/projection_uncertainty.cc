#include "service/geometry/projection_uncertainty.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace monocle {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using IntrinsicsJacobian = Eigen::Matrix<double, 2, kNumIntrinsicParams>;
using RotationJacobian = Eigen::Matrix<double, 2, 3>;

double Median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

double WorstDirectionSigma(const Eigen::Matrix2d& covariance) {
  const Eigen::Vector2d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance, Eigen::EigenvaluesOnly)
          .eigenvalues();
  return std::sqrt(std::max(0.0, eigenvalues.maxCoeff()));
}

// One cell of the grid: its pixel, the ray seen there, and how that ray's pixel moves with
// the intrinsics and with a camera rotation.
struct Cell {
  int index = 0;  // row-major
  Eigen::Vector2d pixel;
  Eigen::Vector2d ray;
  IntrinsicsJacobian j;
  RotationJacobian r;
};

// Cells of a grid of `step_px` over the image, centres kept inside it; cells whose pixel
// the lens model cannot invert are left out.
std::vector<Cell> Cells(const CameraIntrinsics& k, double step_px, int* cols, int* rows) {
  *cols = std::max(1, static_cast<int>(std::ceil(k.width_px / step_px)));
  *rows = std::max(1, static_cast<int>(std::ceil(k.height_px / step_px)));
  std::vector<Cell> cells;
  for (int row = 0; row < *rows; ++row) {
    for (int col = 0; col < *cols; ++col) {
      Cell cell;
      cell.index = row * *cols + col;
      cell.pixel = {std::min((col + 0.5) * step_px, k.width_px - 0.5),
                    std::min((row + 0.5) * step_px, k.height_px - 0.5)};
      const auto ray = PixelToNormalized(k, cell.pixel);
      if (!ray) continue;
      cell.ray = *ray;
      cell.j = PixelJacobianWrtIntrinsics(k, *ray);
      cell.r = PixelJacobianWrtCameraRotation(k, *ray);
      cells.push_back(cell);
    }
  }
  return cells;
}

// The least-squares camera rotation over all cells as a linear map of whatever moves the
// pixels: (sum R'R)^-1 R'.
Eigen::Matrix3d RotationNormal(const std::vector<Cell>& cells) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  for (const auto& c : cells) normal += c.r.transpose() * c.r;
  return normal.inverse();
}

// d(pixel)/d(intrinsics) with the best common rotation taken out: J - R M, where M is the
// rotation that the intrinsics' change causes over the whole image.
std::vector<IntrinsicsJacobian> RelativeJacobians(const std::vector<Cell>& cells) {
  Eigen::Matrix<double, 3, kNumIntrinsicParams> rj =
      Eigen::Matrix<double, 3, kNumIntrinsicParams>::Zero();
  for (const auto& c : cells) rj += c.r.transpose() * c.j;
  const Eigen::Matrix<double, 3, kNumIntrinsicParams> m = RotationNormal(cells) * rj;
  std::vector<IntrinsicsJacobian> out;
  for (const auto& c : cells) out.push_back(c.j - c.r * m);
  return out;
}

ProjectionUncertaintyMap::Summary Summarise(const std::vector<Cell>& cells,
                                            const std::vector<double>& sigma, double centre) {
  ProjectionUncertaintyMap::Summary s;
  std::vector<double> valid;
  for (const auto& c : cells) {
    valid.push_back(sigma[c.index]);
    if (sigma[c.index] > s.worst_px) {
      s.worst_px = sigma[c.index];
      s.worst_at_px = c.pixel;
    }
  }
  s.median_px = Median(valid);
  s.centre_px = centre;
  return s;
}

ProjectionComparison::Figures Figures(const std::vector<double>& differences,
                                      const std::vector<double>& zs) {
  ProjectionComparison::Figures f;
  if (zs.empty()) return f;
  f.median_difference_px = Median(differences);
  f.worst_difference_px = *std::max_element(differences.begin(), differences.end());
  f.median_z = Median(zs);
  f.worst_z = *std::max_element(zs.begin(), zs.end());
  f.fraction_within_1_sigma = std::count_if(zs.begin(), zs.end(), [](double z) { return z <= 1; }) /
                              static_cast<double>(zs.size());
  return f;
}

// sqrt(d' C^-1 d), or NaN where C is singular.
double Mahalanobis(const Eigen::Vector2d& d, const Eigen::Matrix2d& c) {
  if (!(c.determinant() > 0)) return kNaN;
  return std::sqrt(d.dot(c.ldlt().solve(d)));
}

}  // namespace

Eigen::Matrix<double, 2, 3> PixelJacobianWrtCameraRotation(const CameraIntrinsics& k,
                                                           const Eigen::Vector2d& ray) {
  // The ray (x, y, 1) turned by w: (x, y, 1) + w x (x, y, 1), divided by its new z.
  const double x = ray.x(), y = ray.y();
  Eigen::Matrix<double, 2, 3> ray_wrt_rotation;
  ray_wrt_rotation << -x * y, 1 + x * x, -y, -1 - y * y, x * y, x;
  Eigen::Matrix2d pixel_wrt_ray;
  NormalizedToPixel(k, ray, &pixel_wrt_ray);
  return pixel_wrt_ray * ray_wrt_rotation;
}

std::optional<Eigen::Matrix2d> ProjectionCovariance(const CameraIntrinsics& k,
                                                    const IntrinsicsCovariance& covariance,
                                                    const Eigen::Vector2d& pixel) {
  const auto ray = PixelToNormalized(k, pixel);
  if (!ray) return std::nullopt;
  const IntrinsicsJacobian j = PixelJacobianWrtIntrinsics(k, *ray);
  return Eigen::Matrix2d(j * covariance * j.transpose());
}

ProjectionUncertaintyMap MapProjectionUncertainty(const CameraIntrinsics& k,
                                                  const IntrinsicsCovariance& covariance,
                                                  double step_px) {
  ProjectionUncertaintyMap map;
  map.step_px = step_px;
  const auto cells = Cells(k, step_px, &map.cols, &map.rows);
  map.sigma_px.assign(map.cols * map.rows, kNaN);
  map.relative_sigma_px.assign(map.cols * map.rows, kNaN);
  if (cells.empty()) return map;
  const auto relative = RelativeJacobians(cells);
  for (size_t i = 0; i < cells.size(); ++i) {
    const auto& c = cells[i];
    map.sigma_px[c.index] = WorstDirectionSigma(c.j * covariance * c.j.transpose());
    map.relative_sigma_px[c.index] =
        WorstDirectionSigma(relative[i] * covariance * relative[i].transpose());
  }
  // The image's centre: the cell nearest to it.
  const Eigen::Vector2d centre(k.width_px / 2.0, k.height_px / 2.0);
  const auto nearest =
      std::min_element(cells.begin(), cells.end(), [&](const Cell& a, const Cell& b) {
        return (a.pixel - centre).squaredNorm() < (b.pixel - centre).squaredNorm();
      });
  map.absolute = Summarise(cells, map.sigma_px, map.sigma_px[nearest->index]);
  map.relative = Summarise(cells, map.relative_sigma_px, map.relative_sigma_px[nearest->index]);
  return map;
}

ProjectionComparison CompareProjections(const CameraIntrinsics& a,
                                        const IntrinsicsCovariance& covariance_a,
                                        const CameraIntrinsics& b,
                                        const IntrinsicsCovariance& covariance_b, double step_px) {
  int cols = 0, rows = 0;
  const auto cells = Cells(a, step_px, &cols, &rows);
  ProjectionComparison out;
  if (cells.empty()) return out;
  // B's Jacobians at the same rays, for B's share of the covariance.
  std::vector<Cell> cells_b = cells;
  for (auto& c : cells_b) {
    c.j = PixelJacobianWrtIntrinsics(b, c.ray);
    c.r = PixelJacobianWrtCameraRotation(b, c.ray);
  }
  const auto relative_a = RelativeJacobians(cells);
  const auto relative_b = RelativeJacobians(cells_b);
  std::vector<Eigen::Vector2d> difference;
  Eigen::Vector3d rd = Eigen::Vector3d::Zero();
  for (const auto& c : cells) {
    difference.push_back(NormalizedToPixel(b, c.ray) - c.pixel);
    rd += c.r.transpose() * difference.back();
  }
  const Eigen::Vector3d rotation = RotationNormal(cells) * rd;
  std::vector<double> abs_d, abs_z, rel_d, rel_z;
  for (size_t i = 0; i < cells.size(); ++i) {
    const auto& ja = cells[i].j;
    const auto& jb = cells_b[i].j;
    const double z = Mahalanobis(
        difference[i], ja * covariance_a * ja.transpose() + jb * covariance_b * jb.transpose());
    const Eigen::Vector2d turned = difference[i] - cells[i].r * rotation;
    const double zr =
        Mahalanobis(turned, relative_a[i] * covariance_a * relative_a[i].transpose() +
                                relative_b[i] * covariance_b * relative_b[i].transpose());
    if (!std::isfinite(z) || !std::isfinite(zr)) continue;
    abs_d.push_back(difference[i].norm());
    abs_z.push_back(z);
    rel_d.push_back(turned.norm());
    rel_z.push_back(zr);
  }
  out.cells = static_cast<int>(abs_z.size());
  out.absolute = Figures(abs_d, abs_z);
  out.relative = Figures(rel_d, rel_z);
  return out;
}

}  // namespace monocle
