// Pixel -> undistorted pixel, interpolated bilinearly from exact values on a coarse grid.
// The Hough stage undistorts every edge pixel of a frame (thousands); the exact inverse
// (Newton's method in PixelToNormalized) on each was a tenth of a detection's time. The
// grid alone is for coarse work only (half-resolution voting, the first fit that places the
// full-resolution pass along an edge); subpixel measurements take one Newton step on from it
// (Normalized), which leaves them within 1e-6 px of PixelToNormalized's.
// Pure geometry: Eigen only, no I/O.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "service/geometry/camera_model.h"

namespace monocle {

class UndistortionGrid {
 public:
  // Exact values every `cell_px` pixels over the image (one cell beyond each border). By
  // default a hundredth of the focal length: the interpolation error grows with the square
  // of the cell times the distortion's curvature, which scales with 1 / focal.
  explicit UndistortionGrid(const CameraIntrinsics& k, double cell_px = 0);

  // Whether the grid was built for exactly these intrinsics.
  bool IsFor(const CameraIntrinsics& k) const;

  // The pixel where a camera with the same fx, fy, cx, cy and no distortion sees what `px`
  // sees, and optionally d(undistorted px)/d(px). Where the distortion model has no inverse
  // nearby, `px` itself and the identity (as UndistortPixel did before).
  Eigen::Vector2d Undistort(const Eigen::Vector2d& px, Eigen::Matrix2d* jacobian = nullptr) const;

  // Normalized (undistorted) coordinates of `px` as PixelToNormalized gives them, for a third
  // of its time: the grid's value refined by one Newton step on the distortion model, which
  // squares its error (0.01 px) to well under 1e-6 px. Where the grid has no inverse nearby,
  // PixelToNormalized itself (empty where the model has none).
  std::optional<Eigen::Vector2d> Normalized(const Eigen::Vector2d& px) const;

 private:
  CameraIntrinsics k_;
  double cell_px_;
  int nodes_x_, nodes_y_;
  std::vector<Eigen::Vector2d> undistorted_px_;  // row-major nodes, NaN where not invertible
};

// The grid for `k`, built on first use and kept per thread until another camera's is asked
// for (a camera's frames are processed one after another on one thread).
const UndistortionGrid& UndistortionGridFor(const CameraIntrinsics& k);

}  // namespace monocle
