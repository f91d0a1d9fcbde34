#include "service/geometry/undistortion_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

// The exact undistorted pixel, by Newton's method.
Eigen::Vector2d ExactUndistortedPx(const CameraIntrinsics& k, const Eigen::Vector2d& px) {
  const auto n = PixelToNormalized(k, px);
  EXPECT_TRUE(n.has_value()) << px.transpose();
  return {k.fx * n->x() + k.cx, k.fy * n->y() + k.cy};
}

// Over the whole image of the paper's camera and of a wide-angle one, the grid is within
// a fiftieth of a pixel (the half-resolution Hough stage sees half a pixel), and its
// Jacobian rotates a gradient by well under its 0.5 degree angle bins.
TEST(UndistortionGridTest, MatchesTheExactInverseOverTheImage) {
  for (const auto& k : {testing::PaperCamera(), testing::SmallWideAngleCamera()}) {
    const UndistortionGrid grid(k);
    ASSERT_TRUE(grid.IsFor(k));
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, k.width_px - 1), v(0, k.height_px - 1);
    double worst_px = 0, worst_jacobian = 0;
    for (int n = 0; n < 5000; ++n) {
      const Eigen::Vector2d px(u(rng), v(rng));
      Eigen::Matrix2d j;
      const Eigen::Vector2d got = grid.Undistort(px, &j);
      worst_px = std::max(worst_px, (got - ExactUndistortedPx(k, px)).norm());
      // Central differences of the exact inverse.
      Eigen::Matrix2d exact;
      for (int axis = 0; axis < 2; ++axis) {
        const Eigen::Vector2d h = 0.5 * Eigen::Vector2d::Unit(axis);
        exact.col(axis) = ExactUndistortedPx(k, px + h) - ExactUndistortedPx(k, px - h);
      }
      worst_jacobian = std::max(worst_jacobian, (j - exact).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst_px, 0.02) << k;
    EXPECT_LT(worst_jacobian, 0.005) << k;  // 0.3 degrees of a gradient's direction at most
    // And it does undistort: the image corner moves by pixels on both cameras.
    EXPECT_GT((grid.Undistort(Eigen::Vector2d::Zero()) - Eigen::Vector2d::Zero()).norm(), 2);
  }
}

// One Newton step from the grid squares its 0.01 px error: within 1e-6 px of the exact
// inverse over the whole image, on the paper's camera and on a wide-angle one.
TEST(UndistortionGridTest, NormalizedMatchesTheExactInverse) {
  for (const auto& k : {testing::PaperCamera(), testing::SmallWideAngleCamera()}) {
    const UndistortionGrid grid(k);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0, k.width_px - 1), v(0, k.height_px - 1);
    double worst_px = 0;
    for (int n = 0; n < 5000; ++n) {
      const Eigen::Vector2d px(u(rng), v(rng));
      const auto got = grid.Normalized(px);
      const auto exact = PixelToNormalized(k, px);
      ASSERT_TRUE(got.has_value() && exact.has_value()) << px.transpose();
      worst_px = std::max(worst_px,
                          ((*got - *exact).array() * Eigen::Array2d(k.fx, k.fy)).matrix().norm());
    }
    EXPECT_LT(worst_px, 1e-6) << k;
    // Beyond the grid, the exact inverse itself.
    const Eigen::Vector2d far(-100, 5000);
    EXPECT_EQ(grid.Normalized(far).has_value(), PixelToNormalized(k, far).has_value());
    if (const auto n = grid.Normalized(far)) {
      EXPECT_EQ(*n, *PixelToNormalized(k, far));
    }
  }
}

TEST(UndistortionGridTest, KnowsWhichCameraItWasBuiltFor) {
  auto k = testing::PaperCamera();
  const UndistortionGrid grid(k);
  k.distortion[0] += 1e-6;
  EXPECT_FALSE(grid.IsFor(k));
  // Outside the image (beyond the grid's margin) a pixel is left where it is.
  const Eigen::Vector2d far(-100, 5000);
  EXPECT_EQ(grid.Undistort(far), far);
  // Far beyond any int, and NaN: left alone too (no overflowing cast).
  const Eigen::Vector2d huge(1e30, -1e30);
  EXPECT_EQ(grid.Undistort(huge), huge);
  Eigen::Matrix2d j;
  const Eigen::Vector2d nan(std::nan(""), 3);
  EXPECT_TRUE(std::isnan(grid.Undistort(nan, &j).x()));
  EXPECT_EQ(j, Eigen::Matrix2d::Identity());
}

// The shared grid follows the camera asked for: another camera's intrinsics get their own.
TEST(UndistortionGridTest, TheSharedGridIsTheCamerasAskedFor) {
  auto k = testing::PaperCamera();
  const Eigen::Vector2d corner_px(10, 10);
  const Eigen::Vector2d first = UndistortionGridFor(k).Undistort(corner_px);
  EXPECT_TRUE(UndistortionGridFor(k).IsFor(k));
  k.distortion[0] *= 2;
  EXPECT_TRUE(UndistortionGridFor(k).IsFor(k));
  EXPECT_GT((UndistortionGridFor(k).Undistort(corner_px) - first).norm(), 1)
      << "twice the radial distortion moves the image corner further";
  const auto exact = PixelToNormalized(k, corner_px);
  ASSERT_TRUE(exact);
  const Eigen::Vector2d exact_px(k.fx * exact->x() + k.cx, k.fy * exact->y() + k.cy);
  EXPECT_LT((UndistortionGridFor(k).Undistort(corner_px) - exact_px).norm(), 0.01);
}

}  // namespace
}  // namespace monocle
