// Pinhole camera with OpenCV's distortion model (k1 k2 p1 p2 [k3 [k4 k5 k6]]).
// Pure geometry: Eigen only, no I/O.
//
// Frames: camera frame C has X_c along the image's u axis (right), Y_c along v (down),
// Z_c along the optical axis. "Normalized" coordinates are (X_c/Z_c, Y_c/Z_c) before
// distortion, i.e. the paper's (x_1c, y_1c) after undistortion.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <ostream>
#include <string>

namespace monocle {

struct CameraIntrinsics {
  int width_px = 0;
  int height_px = 0;
  double fx = 0, fy = 0;  // pixels
  double cx = 0, cy = 0;  // pixels
  // k1 k2 p1 p2 k3 k4 k5 k6; unused trailing terms are zero.
  std::array<double, 8> distortion{};

  bool HasDistortion() const;
};

std::ostream& operator<<(std::ostream& os, const CameraIntrinsics& k);

// The intrinsic parameters whose uncertainty monocle tracks, in this order:
// fx fy cx cy (pixels), k1 k2 p1 p2 k3 (OpenCV's distortion, dimensionless). Parameters a
// calibration held fixed (e.g. k3 = 0) have zero rows and columns in the covariance.
constexpr int kNumIntrinsicParams = 9;
using IntrinsicsCovariance = Eigen::Matrix<double, kNumIntrinsicParams, kNumIntrinsicParams>;
inline constexpr std::array<const char*, kNumIntrinsicParams> kIntrinsicParamNames = {
    "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};

// d(pixel)/d(fx fy cx cy k1 k2 p1 p2 k3) of a fixed normalized (undistorted) point. Needs
// k4..k6 = 0 (the rational model is not tracked).
Eigen::Matrix<double, 2, kNumIntrinsicParams> PixelJacobianWrtIntrinsics(
    const CameraIntrinsics& k, const Eigen::Vector2d& normalized);

// d(normalized)/d(intrinsics) of a fixed pixel: how the ray of an observed pixel moves when
// the intrinsics change. `normalized_from_pixel` is PixelToNormalized's Jacobian there.
Eigen::Matrix<double, 2, kNumIntrinsicParams> NormalizedJacobianWrtIntrinsics(
    const CameraIntrinsics& k, const Eigen::Vector2d& normalized,
    const Eigen::Matrix2d& normalized_from_pixel);

using IntrinsicParams = Eigen::Matrix<double, kNumIntrinsicParams, 1>;

// The tracked parameters of `k`, in the order above.
IntrinsicParams IntrinsicParamsOf(const CameraIntrinsics& k);

// Adds `delta` (in the order above) to the intrinsics; for numeric checks and propagation.
CameraIntrinsics PerturbIntrinsics(const CameraIntrinsics& k,
                                   const Eigen::Matrix<double, kNumIntrinsicParams, 1>& delta);

// Normalized (undistorted) -> distorted normalized coordinates, and optionally the 2x2
// Jacobian d(distorted)/d(normalized).
Eigen::Vector2d Distort(const CameraIntrinsics& k, const Eigen::Vector2d& normalized,
                        Eigen::Matrix2d* jacobian = nullptr);

// Normalized (undistorted) -> pixel.
Eigen::Vector2d NormalizedToPixel(const CameraIntrinsics& k, const Eigen::Vector2d& normalized,
                                  Eigen::Matrix2d* jacobian = nullptr);

// Point in the camera frame (metres) -> pixel. Requires p_camera.z() > 0.
Eigen::Vector2d ProjectToPixel(const CameraIntrinsics& k, const Eigen::Vector3d& p_camera);

// Pixel -> normalized (undistorted) coordinates by Newton's method on the distortion
// model; converges to ~1e-15. Optionally returns d(normalized)/d(pixel).
// Empty when the pixel lies where the distortion model is not invertible.
std::optional<Eigen::Vector2d> PixelToNormalized(const CameraIntrinsics& k,
                                                 const Eigen::Vector2d& pixel,
                                                 Eigen::Matrix2d* jacobian = nullptr);

}  // namespace monocle
