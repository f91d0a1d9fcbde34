#include "service/geometry/projection_uncertainty.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

// A covariance with correlations and every parameter uncertain, small enough to be linear.
IntrinsicsCovariance SomeCovariance() {
  IntrinsicParams sigma;
  sigma << 0.8, 0.8, 1.5, 1.2, 0.004, 0.01, 0.0002, 0.0002, 0.01;
  IntrinsicsCovariance correlation = IntrinsicsCovariance::Identity();
  correlation(0, 1) = correlation(1, 0) = 0.9;   // fx, fy
  correlation(4, 5) = correlation(5, 4) = -0.8;  // k1, k2
  correlation(5, 8) = correlation(8, 5) = -0.7;  // k2, k3
  return sigma.asDiagonal() * correlation * sigma.asDiagonal();
}

// Round trip: intrinsics drawn from the covariance move a fixed ray's pixel with the spread
// that J C J' predicts.
TEST(ProjectionUncertaintyTest, MatchesIntrinsicsDrawnFromTheCovariance) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  const IntrinsicsCovariance covariance = SomeCovariance();
  const Eigen::Matrix<double, kNumIntrinsicParams, kNumIntrinsicParams> root =
      covariance.llt().matrixL();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(20, 20), Eigen::Vector2d(640, 512), Eigen::Vector2d(1200, 300)}) {
    const auto ray = PixelToNormalized(k, pixel);
    ASSERT_TRUE(ray);
    Eigen::Matrix2d sampled = Eigen::Matrix2d::Zero();
    constexpr int kDraws = 20000;
    for (int i = 0; i < kDraws; ++i) {
      IntrinsicParams draw;
      for (auto& d : draw) d = normal(rng);
      const Eigen::Vector2d moved = NormalizedToPixel(PerturbIntrinsics(k, root * draw), *ray);
      sampled += (moved - pixel) * (moved - pixel).transpose() / kDraws;
    }
    const auto predicted = ProjectionCovariance(k, covariance, pixel);
    ASSERT_TRUE(predicted);
    for (int a = 0; a < 2; ++a)
      EXPECT_NEAR(std::sqrt(sampled(a, a)), std::sqrt((*predicted)(a, a)),
                  0.04 * std::sqrt((*predicted)(a, a)))
          << pixel.transpose();
  }
}

// An uncertain principal point moves every ray's pixel alike (absolute), and is nearly all a
// camera rotation (relative).
TEST(ProjectionUncertaintyTest, ThePrincipalPointAloneIsTheSameEverywhere) {
  const CameraIntrinsics k = testing::PaperCamera();
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  covariance(2, 2) = 0.5 * 0.5;
  covariance(3, 3) = 0.3 * 0.3;
  const auto map = MapProjectionUncertainty(k, covariance, 64);
  EXPECT_EQ(map.cols, 20);
  EXPECT_EQ(map.rows, 16);
  EXPECT_NEAR(map.absolute.median_px, 0.5, 1e-9);
  EXPECT_NEAR(map.absolute.worst_px, 0.5, 1e-9);
  EXPECT_NEAR(map.absolute.centre_px, 0.5, 1e-9);
  EXPECT_LT(map.relative.median_px, 0.1 * map.absolute.median_px);
  EXPECT_LT(map.relative.worst_px, 0.2 * map.absolute.worst_px);
}

// The rotation Jacobian against turning the ray for real.
TEST(ProjectionUncertaintyTest, RotationJacobianMatchesTurningTheRay) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  for (const Eigen::Vector2d& pixel : {Eigen::Vector2d(30, 40), Eigen::Vector2d(700, 500)}) {
    const auto ray = PixelToNormalized(k, pixel);
    ASSERT_TRUE(ray);
    const auto analytic = PixelJacobianWrtCameraRotation(k, *ray);
    for (int axis = 0; axis < 3; ++axis) {
      constexpr double kStep = 1e-6;
      const Eigen::Vector3d turned =
          Eigen::AngleAxisd(kStep, Eigen::Vector3d::Unit(axis)) * ray->homogeneous();
      const Eigen::Vector2d numeric = (ProjectToPixel(k, turned) - pixel) / kStep;
      EXPECT_NEAR((numeric - analytic.col(axis)).norm(), 0, 1e-4 * analytic.col(axis).norm())
          << pixel.transpose() << " axis " << axis;
    }
  }
}

// Round trip of the relative figure: intrinsics drawn from the covariance, each draw's pixel
// shifts over the grid with the best rotation (fitted here by turning rays for real) taken
// out, spread as predicted.
TEST(ProjectionUncertaintyTest, RelativeMatchesDrawsWithTheirBestRotationRemoved) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  const IntrinsicsCovariance covariance = SomeCovariance() * 0.01;  // well inside linearity
  constexpr double kStep = 128;
  const auto map = MapProjectionUncertainty(k, covariance, kStep);
  std::vector<Eigen::Vector2d> pixels, rays;
  std::vector<Eigen::Matrix<double, 2, 3>> turn;  // numeric d(pixel)/d(rotation)
  for (int r = 0; r < map.rows; ++r) {
    for (int c = 0; c < map.cols; ++c) {
      const Eigen::Vector2d pixel(std::min((c + 0.5) * kStep, k.width_px - 0.5),
                                  std::min((r + 0.5) * kStep, k.height_px - 0.5));
      const auto ray = PixelToNormalized(k, pixel);
      ASSERT_TRUE(ray);
      Eigen::Matrix<double, 2, 3> t;
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d turned =
            Eigen::AngleAxisd(1e-6, Eigen::Vector3d::Unit(axis)) * ray->homogeneous();
        t.col(axis) = (ProjectToPixel(k, turned) - pixel) / 1e-6;
      }
      pixels.push_back(pixel);
      rays.push_back(*ray);
      turn.push_back(t);
    }
  }
  const size_t n = pixels.size();
  Eigen::MatrixXd stacked_turn(2 * n, 3);
  for (size_t i = 0; i < n; ++i) stacked_turn.middleRows(2 * i, 2) = turn[i];
  const Eigen::Matrix<double, kNumIntrinsicParams, kNumIntrinsicParams> root =
      covariance.llt().matrixL();
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  constexpr int kDraws = 4000;
  std::vector<Eigen::Matrix2d> sampled(n, Eigen::Matrix2d::Zero());
  for (int d = 0; d < kDraws; ++d) {
    IntrinsicParams draw;
    for (auto& v : draw) v = normal(rng);
    const CameraIntrinsics moved = PerturbIntrinsics(k, root * draw);
    Eigen::VectorXd shift(2 * n);
    for (size_t i = 0; i < n; ++i)
      shift.segment<2>(2 * i) = NormalizedToPixel(moved, rays[i]) - pixels[i];
    const Eigen::Vector3d best = stacked_turn.colPivHouseholderQr().solve(shift);
    const Eigen::VectorXd left = shift - stacked_turn * best;
    for (size_t i = 0; i < n; ++i)
      sampled[i] += left.segment<2>(2 * i) * left.segment<2>(2 * i).transpose() / kDraws;
  }
  for (size_t i = 0; i < n; ++i) {
    const double sampled_worst = std::sqrt(
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(sampled[i]).eigenvalues().maxCoeff());
    const int col = static_cast<int>(i) % map.cols, row = static_cast<int>(i) / map.cols;
    EXPECT_NEAR(sampled_worst, map.RelativeAt(col, row), 0.06 * map.RelativeAt(col, row))
        << pixels[i].transpose();
  }
}

// Uncertain distortion: sure at the centre, unsure at the image's corners, worst there.
TEST(ProjectionUncertaintyTest, UncertainDistortionGrowsTowardsTheCorners) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  covariance(4, 4) = 0.003 * 0.003;
  const auto map = MapProjectionUncertainty(k, covariance, 32);
  for (const auto& s : {map.absolute, map.relative}) {
    EXPECT_LT(s.centre_px, 0.01);
    EXPECT_GT(s.worst_px, 0.3);
    EXPECT_GT(s.worst_px, 3 * s.median_px);
    const bool at_a_corner = (s.worst_at_px.x() < 32 || s.worst_at_px.x() > k.width_px - 32) &&
                             (s.worst_at_px.y() < 32 || s.worst_at_px.y() > k.height_px - 32);
    EXPECT_TRUE(at_a_corner) << s.worst_at_px.transpose();
  }
}

// Two calibrations a principal point apart, each sure of it to s: the ray lands d apart
// everywhere, d / (s sqrt 2) in their combined 1 sigma.
TEST(ProjectionUncertaintyTest, ComparisonMeasuresTheDifferenceInCombinedSigma) {
  const CameraIntrinsics a = testing::PaperCamera();
  CameraIntrinsics b = a;
  b.cx += 1.0;
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  covariance(2, 2) = covariance(3, 3) = 0.5 * 0.5;
  const auto same = CompareProjections(a, covariance, a, covariance, 64);
  EXPECT_EQ(same.cells, 320);
  EXPECT_NEAR(same.absolute.worst_difference_px, 0, 1e-9);
  EXPECT_NEAR(same.relative.worst_difference_px, 0, 1e-9);
  EXPECT_DOUBLE_EQ(same.absolute.fraction_within_1_sigma, 1.0);
  const auto apart = CompareProjections(a, covariance, b, covariance, 64);
  EXPECT_NEAR(apart.absolute.median_difference_px, 1.0, 1e-9);
  EXPECT_NEAR(apart.absolute.median_z, 1.0 / (0.5 * std::sqrt(2.0)), 1e-6);
  EXPECT_DOUBLE_EQ(apart.absolute.fraction_within_1_sigma, 0.0);
  // A principal point moved is nearly a pan: little is left once the rotation is out.
  EXPECT_LT(apart.relative.median_difference_px, 0.05);
}

}  // namespace
}  // namespace monocle
