#include "service/geometry/undistortion_grid.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace monocle {

UndistortionGrid::UndistortionGrid(const CameraIntrinsics& k, double cell_px)
    : k_(k), cell_px_(cell_px > 0 ? cell_px : std::clamp(0.005 * (k.fx + k.fy), 2.0, 32.0)) {
  // Nodes at -cell, 0, cell, ... up to one cell past the last pixel.
  nodes_x_ = static_cast<int>(std::ceil((k.width_px - 1) / cell_px_)) + 3;
  nodes_y_ = static_cast<int>(std::ceil((k.height_px - 1) / cell_px_)) + 3;
  undistorted_px_.resize(static_cast<size_t>(nodes_x_) * nodes_y_);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int j = 0; j < nodes_y_; ++j) {
    for (int i = 0; i < nodes_x_; ++i) {
      const Eigen::Vector2d px((i - 1) * cell_px_, (j - 1) * cell_px_);
      const auto n = PixelToNormalized(k, px);
      undistorted_px_[static_cast<size_t>(j) * nodes_x_ + i] =
          n ? Eigen::Vector2d(k.fx * n->x() + k.cx, k.fy * n->y() + k.cy)
            : Eigen::Vector2d(nan, nan);
    }
  }
}

bool UndistortionGrid::IsFor(const CameraIntrinsics& k) const {
  return k.width_px == k_.width_px && k.height_px == k_.height_px && k.fx == k_.fx &&
         k.fy == k_.fy && k.cx == k_.cx && k.cy == k_.cy && k.distortion == k_.distortion;
}

Eigen::Vector2d UndistortionGrid::Undistort(const Eigen::Vector2d& px,
                                            Eigen::Matrix2d* jacobian) const {
  if (jacobian != nullptr) jacobian->setIdentity();
  const double gx = px.x() / cell_px_ + 1, gy = px.y() / cell_px_ + 1;
  // Outside the grid (or NaN): checked before the cast, which would overflow far outside.
  if (!(gx >= 0 && gy >= 0 && gx <= nodes_x_ - 1 && gy <= nodes_y_ - 1)) return px;
  const int i = std::min(static_cast<int>(gx), nodes_x_ - 2);
  const int j = std::min(static_cast<int>(gy), nodes_y_ - 2);
  const double fx = gx - i, fy = gy - j;
  const Eigen::Vector2d* row0 = &undistorted_px_[static_cast<size_t>(j) * nodes_x_ + i];
  const Eigen::Vector2d* row1 = row0 + nodes_x_;
  const Eigen::Vector2d a = row0[0], b = row0[1], c = row1[0], d = row1[1];
  if (!(a.allFinite() && b.allFinite() && c.allFinite() && d.allFinite())) return px;
  if (jacobian != nullptr) {
    jacobian->col(0) = ((1 - fy) * (b - a) + fy * (d - c)) / cell_px_;
    jacobian->col(1) = ((1 - fx) * (c - a) + fx * (d - b)) / cell_px_;
  }
  return (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * d);
}

std::optional<Eigen::Vector2d> UndistortionGrid::Normalized(const Eigen::Vector2d& px) const {
  const double gx = px.x() / cell_px_ + 1, gy = px.y() / cell_px_ + 1;
  if (!(gx >= 0 && gy >= 0 && gx <= nodes_x_ - 1 && gy <= nodes_y_ - 1))
    return PixelToNormalized(k_, px);
  const int i = std::min(static_cast<int>(gx), nodes_x_ - 2);
  const int j = std::min(static_cast<int>(gy), nodes_y_ - 2);
  const Eigen::Vector2d* row0 = &undistorted_px_[static_cast<size_t>(j) * nodes_x_ + i];
  const Eigen::Vector2d* row1 = row0 + nodes_x_;
  if (!(row0[0].allFinite() && row0[1].allFinite() && row1[0].allFinite() && row1[1].allFinite())) {
    return PixelToNormalized(k_, px);
  }
  const Eigen::Vector2d u = Undistort(px);
  const Eigen::Vector2d start((u.x() - k_.cx) / k_.fx, (u.y() - k_.cy) / k_.fy);
  const Eigen::Vector2d target((px.x() - k_.cx) / k_.fx, (px.y() - k_.cy) / k_.fy);
  Eigen::Matrix2d jacobian;
  const Eigen::Vector2d residual = Distort(k_, start, &jacobian) - target;
  // Beyond the fold of the polynomial the model is not the lens (PixelToNormalized says so).
  if (!(jacobian.determinant() > 1e-9)) return PixelToNormalized(k_, px);
  return Eigen::Vector2d(start - jacobian.inverse() * residual);
}

const UndistortionGrid& UndistortionGridFor(const CameraIntrinsics& k) {
  thread_local std::optional<UndistortionGrid> grid;
  if (!grid || !grid->IsFor(k)) grid.emplace(k);
  return *grid;
}

}  // namespace monocle
