#include "service/geometry/camera_model.h"

#include <Eigen/LU>
#include <cmath>

namespace monocle {

bool CameraIntrinsics::HasDistortion() const {
  for (double d : distortion) {
    if (d != 0.0) return true;
  }
  return false;
}

std::ostream& operator<<(std::ostream& os, const CameraIntrinsics& k) {
  os << "CameraIntrinsics{" << k.width_px << "x" << k.height_px << " fx=" << k.fx << " fy=" << k.fy
     << " cx=" << k.cx << " cy=" << k.cy << " d=[";
  for (size_t i = 0; i < k.distortion.size(); ++i) os << (i ? " " : "") << k.distortion[i];
  return os << "]}";
}

Eigen::Vector2d Distort(const CameraIntrinsics& k, const Eigen::Vector2d& n,
                        Eigen::Matrix2d* jacobian) {
  const auto& d = k.distortion;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4], k4 = d[5], k5 = d[6],
               k6 = d[7];
  const double x = n.x(), y = n.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double a = 1 + k1 * r2 + k2 * r4 + k3 * r6;
  const double b = 1 + k4 * r2 + k5 * r4 + k6 * r6;
  const double radial = a / b;
  const Eigen::Vector2d out(x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                            y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y);
  if (jacobian != nullptr) {
    const double da = k1 + 2 * k2 * r2 + 3 * k3 * r4;
    const double db = k4 + 2 * k5 * r2 + 3 * k6 * r4;
    const double dradial_dr2 = (da * b - a * db) / (b * b);
    (*jacobian)(0, 0) = radial + 2 * x * x * dradial_dr2 + 2 * p1 * y + 6 * p2 * x;
    (*jacobian)(0, 1) = 2 * x * y * dradial_dr2 + 2 * p1 * x + 2 * p2 * y;
    (*jacobian)(1, 0) = 2 * x * y * dradial_dr2 + 2 * p1 * x + 2 * p2 * y;
    (*jacobian)(1, 1) = radial + 2 * y * y * dradial_dr2 + 6 * p1 * y + 2 * p2 * x;
  }
  return out;
}

Eigen::Vector2d NormalizedToPixel(const CameraIntrinsics& k, const Eigen::Vector2d& normalized,
                                  Eigen::Matrix2d* jacobian) {
  const Eigen::Vector2d d = Distort(k, normalized, jacobian);
  if (jacobian != nullptr) {
    jacobian->row(0) *= k.fx;
    jacobian->row(1) *= k.fy;
  }
  return {k.fx * d.x() + k.cx, k.fy * d.y() + k.cy};
}

Eigen::Vector2d ProjectToPixel(const CameraIntrinsics& k, const Eigen::Vector3d& p_camera) {
  return NormalizedToPixel(k, p_camera.head<2>() / p_camera.z());
}

std::optional<Eigen::Vector2d> PixelToNormalized(const CameraIntrinsics& k,
                                                 const Eigen::Vector2d& pixel,
                                                 Eigen::Matrix2d* jacobian) {
  const Eigen::Vector2d target((pixel.x() - k.cx) / k.fx, (pixel.y() - k.cy) / k.fy);
  if (!k.HasDistortion()) {
    if (jacobian != nullptr) *jacobian << 1 / k.fx, 0, 0, 1 / k.fy;
    return target;
  }
  // Newton on Distort(n) = target, starting from the distorted point itself; the model is
  // smooth and near-identity over a real lens's field, so a handful of steps suffice.
  Eigen::Vector2d n = target;
  Eigen::Matrix2d j;
  constexpr int kMaxIterations = 30;
  for (int i = 0; i < kMaxIterations; ++i) {
    const Eigen::Vector2d residual = Distort(k, n, &j) - target;
    const double det = j.determinant();
    if (!(std::abs(det) > 1e-9)) return std::nullopt;
    const Eigen::Vector2d step = j.inverse() * residual;
    n -= step;
    if (step.squaredNorm() < 1e-30 || residual.squaredNorm() < 1e-32) {
      if (jacobian != nullptr) {
        Distort(k, n, &j);
        Eigen::Matrix2d pixel_to_distorted;
        pixel_to_distorted << 1 / k.fx, 0, 0, 1 / k.fy;
        *jacobian = j.inverse() * pixel_to_distorted;
      }
      // Reject a root beyond the fold of the polynomial, where the model is not the lens.
      if (j.determinant() <= 0) return std::nullopt;
      return n;
    }
  }
  // Accept a slowly converging root if it reproduces the pixel to 1e-9 px.
  const Eigen::Vector2d residual = Distort(k, n, &j) - target;
  if (residual.cwiseProduct(Eigen::Vector2d(k.fx, k.fy)).norm() > 1e-9 || j.determinant() <= 0) {
    return std::nullopt;
  }
  if (jacobian != nullptr) {
    Eigen::Matrix2d pixel_to_distorted;
    pixel_to_distorted << 1 / k.fx, 0, 0, 1 / k.fy;
    *jacobian = j.inverse() * pixel_to_distorted;
  }
  return n;
}

Eigen::Matrix<double, 2, kNumIntrinsicParams> PixelJacobianWrtIntrinsics(const CameraIntrinsics& k,
                                                                         const Eigen::Vector2d& n) {
  const Eigen::Vector2d d = Distort(k, n);
  const double x = n.x(), y = n.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  // Distorted coordinates are linear in k1 k2 p1 p2 k3 (with k4..k6 = 0).
  Eigen::Matrix<double, 2, 5> dd;
  dd << x * r2, x * r4, 2 * x * y, r2 + 2 * x * x, x * r6,  //
      y * r2, y * r4, r2 + 2 * y * y, 2 * x * y, y * r6;
  Eigen::Matrix<double, 2, kNumIntrinsicParams> j = Eigen::Matrix<double, 2, 9>::Zero();
  j(0, 0) = d.x();
  j(1, 1) = d.y();
  j(0, 2) = 1;
  j(1, 3) = 1;
  j.block<1, 5>(0, 4) = k.fx * dd.row(0);
  j.block<1, 5>(1, 4) = k.fy * dd.row(1);
  return j;
}

Eigen::Matrix<double, 2, kNumIntrinsicParams> NormalizedJacobianWrtIntrinsics(
    const CameraIntrinsics& k, const Eigen::Vector2d& normalized,
    const Eigen::Matrix2d& normalized_from_pixel) {
  // The pixel is fixed: 0 = d(pixel)/dn * dn + d(pixel)/d(theta) * d(theta).
  return -normalized_from_pixel * PixelJacobianWrtIntrinsics(k, normalized);
}

IntrinsicParams IntrinsicParamsOf(const CameraIntrinsics& k) {
  IntrinsicParams p;
  p << k.fx, k.fy, k.cx, k.cy, k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3],
      k.distortion[4];
  return p;
}

CameraIntrinsics PerturbIntrinsics(const CameraIntrinsics& k,
                                   const Eigen::Matrix<double, kNumIntrinsicParams, 1>& delta) {
  CameraIntrinsics out = k;
  out.fx += delta[0];
  out.fy += delta[1];
  out.cx += delta[2];
  out.cy += delta[3];
  for (int i = 0; i < 5; ++i) out.distortion[i] += delta[4 + i];
  return out;
}

}  // namespace monocle
