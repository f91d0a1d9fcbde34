// How sure a calibration is of where a ray lands in the image, from the intrinsics'
// covariance, across the image, two ways:
// - absolute: a ray fixed in the camera frame. It counts the principal point's uncertainty in
//   full, as a measurement made straight through these intrinsics (a corner pose's angles)
//   does.
// - relative: after the small camera rotation that best explains the change over the whole
//   image, which a later extrinsic calibration (the floor's) absorbs. What is left is where the
//   lens model itself is unsure: the regions no board reached. mrcal's projection uncertainty
//   and projection_diff remove the same freedom their own ways.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "service/geometry/camera_model.h"

namespace monocle {

// d(pixel)/d(rotation vector) of the ray seen at `pixel` when the camera turns by a small
// rotation (camera frame, radians): 2x3. `ray` is that pixel's normalized coordinates.
Eigen::Matrix<double, 2, 3> PixelJacobianWrtCameraRotation(const CameraIntrinsics& k,
                                                           const Eigen::Vector2d& ray);

// The 2x2 covariance (px^2) of where the ray seen at `pixel` lands when the intrinsics vary
// by `covariance` (absolute): J C J' with J = d(pixel)/d(intrinsics) at that ray. Empty
// where the lens model cannot be inverted.
std::optional<Eigen::Matrix2d> ProjectionCovariance(const CameraIntrinsics& k,
                                                    const IntrinsicsCovariance& covariance,
                                                    const Eigen::Vector2d& pixel);

struct ProjectionUncertaintyMap {
  int cols = 0, rows = 0;
  double step_px = 0;  // cell (c, r) is centred on pixel ((c + 0.5) step, (r + 0.5) step)
  // Worst-direction 1 sigma per cell, row-major, px; NaN where the model is not invertible.
  std::vector<double> sigma_px;           // absolute
  std::vector<double> relative_sigma_px;  // after the best common rotation

  struct Summary {
    double centre_px = 0;  // at the image's centre
    double median_px = 0;  // over the cells
    double worst_px = 0;
    Eigen::Vector2d worst_at_px = Eigen::Vector2d::Zero();
  };
  Summary absolute, relative;

  double At(int col, int row) const { return sigma_px[row * cols + col]; }
  double RelativeAt(int col, int row) const { return relative_sigma_px[row * cols + col]; }
};

// Cells of `step_px` over the whole image (the last row and column may reach past its edge
// by less than a cell; their centres are kept inside it).
ProjectionUncertaintyMap MapProjectionUncertainty(const CameraIntrinsics& k,
                                                  const IntrinsicsCovariance& covariance,
                                                  double step_px = 16);

// Two calibrations of one camera compared where it matters: for each cell, the ray that A
// sees at the cell's pixel, projected by B; absolute, and relative (B's pixels turned by the
// rotation that best matches A's over the image). Honest 1 sigmas make the difference's
// Mahalanobis length z (under A's and B's projection covariances, the same way) a 2-D chi:
// median 1.18, 39 % within 1.
struct ProjectionComparison {
  struct Figures {
    double median_difference_px = 0;
    double worst_difference_px = 0;
    double median_z = 0;
    double worst_z = 0;
    double fraction_within_1_sigma = 0;
  };
  Figures absolute, relative;
  int cells = 0;
};

ProjectionComparison CompareProjections(const CameraIntrinsics& a,
                                        const IntrinsicsCovariance& covariance_a,
                                        const CameraIntrinsics& b,
                                        const IntrinsicsCovariance& covariance_b,
                                        double step_px = 16);

}  // namespace monocle
