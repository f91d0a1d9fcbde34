#include "service/geometry/corner_intrinsics_uncertainty.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <random>

#include "service/geometry/corner_pose_refinement.h"
#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

const CornerPose kTruth{2.0, 1.5, 1.6, 2.2143, 0.9, 0.1};

// Pixels along each axis's image as the true intrinsics see it, from near the corner out.
CornerEdgePixels EdgesSeenBy(const CameraIntrinsics& k, const CornerPose& pose) {
  CornerEdgePixels edges;
  const Eigen::Matrix3d r = RotationCameraFromCorner(pose);
  for (int axis = 0; axis < 3; ++axis) {
    const auto image = ImageOfAxis(r, CameraPosition(pose), axis);
    EXPECT_TRUE(image.has_value());
    for (double s = 0.02; s < 0.25; s += 0.004) {
      const Eigen::Vector2d px = NormalizedToPixel(k, image->corner + s * image->direction);
      if (px.x() > 0 && px.y() > 0 && px.x() < k.width_px && px.y() < k.height_px)
        edges.points_px[axis].push_back(px);
    }
    edges.fitted_points[axis] = static_cast<int>(edges.points_px[axis].size());
  }
  return edges;
}

// The pose a locator with intrinsics `k` fits to the pixels: every point's ray, each edge's
// line by its centroid and principal direction, then the refinement. Written here apart from
// the code under test.
CornerPose FitAsLocatorWould(const CameraIntrinsics& k, const CornerEdgePixels& edges) {
  std::array<LineObservation, 3> lines;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<Eigen::Vector2d> rays;
    for (const auto& px : edges.points_px[axis]) rays.push_back(*PixelToNormalized(k, px));
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : rays) mean += p / static_cast<double>(rays.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : rays) scatter += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    Eigen::Vector2d d = eig.eigenvectors().col(1);
    if (d.dot(rays.back() - rays.front()) < 0) d = -d;  // from the corner out
    lines[axis].centroid = mean;
    lines[axis].direction = d;
    lines[axis].spread = std::sqrt(eig.eigenvalues()(1) / static_cast<double>(rays.size()));
    lines[axis].num_points = static_cast<int>(rays.size());
  }
  return RefineCornerPose(kTruth, lines, {0, 1, 2}, k.fx, 1.0).value().pose;
}

// A calibration's typical uncertainty: focal lengths 2 px (correlated), principal point 3 px,
// radial terms, small tangential ones; k3 held fixed.
IntrinsicsCovariance TypicalCalibrationCovariance() {
  IntrinsicParams sigma;
  sigma << 2.0, 2.0, 3.0, 3.0, 0.01, 0.02, 0.0005, 0.0005, 0.0;
  IntrinsicsCovariance c = (sigma.array().square()).matrix().asDiagonal();
  c(0, 1) = c(1, 0) = 0.9 * sigma[0] * sigma[1];
  return c;
}

TEST(CornerIntrinsicsUncertaintyTest, NoCovarianceAddsNothing) {
  const CameraIntrinsics k = testing::PaperCamera();
  const auto added = CornerPoseCovarianceFromIntrinsics(k, kTruth, EdgesSeenBy(k, kTruth),
                                                        IntrinsicsCovariance::Zero());
  EXPECT_TRUE(added.isZero());
}

// Intrinsics drawn from their covariance, the same perfect pixels fitted with each: the
// pose's errors fall within the propagated 1 sigma about 68 % of the time, per coordinate.
TEST(CornerIntrinsicsUncertaintyTest, PropagatedSigmaCoversPosesFittedWithDrawnIntrinsics) {
  const CameraIntrinsics k = testing::PaperCamera();
  const CornerEdgePixels edges = EdgesSeenBy(k, kTruth);
  const IntrinsicsCovariance c = TypicalCalibrationCovariance();
  const Eigen::Matrix<double, 5, 5> added = CornerPoseCovarianceFromIntrinsics(k, kTruth, edges, c);
  const Eigen::Matrix<double, 5, 1> sigma = added.diagonal().cwiseSqrt();
  // A 2 px focal error alone moves a camera 2.5 m from the corner by about 3 mm.
  EXPECT_GT(sigma[0], 5e-4) << sigma.transpose();
  EXPECT_GT(sigma[2], 1e-4) << sigma.transpose();

  const Eigen::LLT<IntrinsicsCovariance> llt(c + 1e-18 * IntrinsicsCovariance::Identity());
  std::mt19937 rng(20261129);
  std::normal_distribution<double> normal;
  constexpr int kDraws = 400;
  Eigen::Matrix<int, 5, 1> within = Eigen::Matrix<int, 5, 1>::Zero();
  const CornerPose fitted_truth = FitAsLocatorWould(k, edges);
  for (int i = 0; i < kDraws; ++i) {
    IntrinsicParams z;
    for (int j = 0; j < kNumIntrinsicParams; ++j) z[j] = normal(rng);
    const CornerPose p = FitAsLocatorWould(PerturbIntrinsics(k, llt.matrixL() * z), edges);
    const double error[5] = {
        p.x_m - fitted_truth.x_m, p.y_m - fitted_truth.y_m,
        std::remainder(p.pan_rad - fitted_truth.pan_rad, 2 * std::numbers::pi),
        p.tilt_rad - fitted_truth.tilt_rad,
        std::remainder(p.swing_rad - fitted_truth.swing_rad, 2 * std::numbers::pi)};
    for (int d = 0; d < 5; ++d) within[d] += std::abs(error[d]) <= sigma[d];
  }
  for (int d = 0; d < 5; ++d) {
    const double fraction = within[d] / static_cast<double>(kDraws);
    EXPECT_GT(fraction, 0.62) << "coordinate " << d;
    EXPECT_LT(fraction, 0.74) << "coordinate " << d;
  }
}

}  // namespace
}  // namespace monocle
