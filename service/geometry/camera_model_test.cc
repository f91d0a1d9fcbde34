#include "service/geometry/camera_model.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

CameraIntrinsics RationalCamera() {
  CameraIntrinsics k = testing::PaperCamera();
  k.distortion = {0.3, -0.05, 0.001, 0.002, 0.01, 0.4, -0.02, 0.005};
  return k;
}

TEST(CameraModelTest, UndistortInvertsDistortToMachinePrecision) {
  std::mt19937_64 rng(7);
  for (const auto& k :
       {testing::PaperCamera(), testing::WideAnglePaperCamera(), RationalCamera()}) {
    std::uniform_real_distribution<double> u(0, k.width_px - 1), v(0, k.height_px - 1);
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector2d px(u(rng), v(rng));
      const auto n = PixelToNormalized(k, px);
      ASSERT_TRUE(n.has_value()) << k << " px " << px.transpose();
      EXPECT_LT((NormalizedToPixel(k, *n) - px).norm(), 1e-9) << k;
    }
  }
}

TEST(CameraModelTest, ProjectionMatchesOpenCv) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> xy(-0.45, 0.45), z(0.5, 5);
  for (const auto& k :
       {testing::PaperCamera(), testing::WideAnglePaperCamera(), RationalCamera()}) {
    const cv::Matx33d camera_matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const std::vector<double> dist(k.distortion.begin(), k.distortion.end());
    for (int i = 0; i < 200; ++i) {
      const double depth = z(rng);
      const Eigen::Vector3d p(xy(rng) * depth, xy(rng) * depth, depth);
      std::vector<cv::Point3d> obj{{p.x(), p.y(), p.z()}};
      std::vector<cv::Point2d> img;
      cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix, dist, img);
      const Eigen::Vector2d ours = ProjectToPixel(k, p);
      EXPECT_NEAR(ours.x(), img[0].x, 1e-7);
      EXPECT_NEAR(ours.y(), img[0].y, 1e-7);
    }
  }
}

TEST(CameraModelTest, UndistortionAgreesWithOpenCvAndIsTighter) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  const cv::Matx33d camera_matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const std::vector<double> dist(k.distortion.begin(), k.distortion.end());
  const std::vector<cv::Point2d> corners{{0, 0}, {1279, 0}, {0, 1023}, {1279, 1023}, {640, 512}};
  std::vector<cv::Point2d> cv_default, cv_iterated;
  cv::undistortPoints(corners, cv_default, camera_matrix, dist);
  cv::undistortPoints(
      corners, cv_iterated, camera_matrix, dist, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-12));
  double default_error = 0;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d px(corners[i].x, corners[i].y);
    const auto n = PixelToNormalized(k, px);
    ASSERT_TRUE(n.has_value());
    EXPECT_NEAR(n->x(), cv_iterated[i].x, 1e-6);
    EXPECT_NEAR(n->y(), cv_iterated[i].y, 1e-6);
    default_error = std::max(
        default_error,
        (NormalizedToPixel(k, Eigen::Vector2d(cv_default[i].x, cv_default[i].y)) - px).norm());
    EXPECT_LT((NormalizedToPixel(k, *n) - px).norm(), 1e-9);
  }
  // OpenCV's default (5 fixed iterations) leaves a visible error in the corners of a wide
  // lens; this is why the geometry does its own Newton inversion.
  EXPECT_GT(default_error, 1e-3);
}

TEST(CameraModelTest, UndistortJacobianMatchesFiniteDifferences) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  const Eigen::Vector2d px(100.3, 900.7);
  Eigen::Matrix2d j;
  ASSERT_TRUE(PixelToNormalized(k, px, &j).has_value());
  const double h = 1e-4;
  for (int a = 0; a < 2; ++a) {
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    d[a] = h;
    const Eigen::Vector2d numeric =
        (*PixelToNormalized(k, px + d) - *PixelToNormalized(k, px - d)) / (2 * h);
    EXPECT_NEAR((j.col(a) - numeric).norm(), 0, 1e-10);
  }
}

TEST(CameraModelTest, NoDistortionIsPlainPinhole) {
  CameraIntrinsics k = testing::PaperCamera();
  k.distortion = {};
  const auto n = PixelToNormalized(k, Eigen::Vector2d(k.cx + k.fx * 0.1, k.cy - k.fy * 0.2));
  ASSERT_TRUE(n.has_value());
  EXPECT_NEAR(n->x(), 0.1, 1e-15);
  EXPECT_NEAR(n->y(), -0.2, 1e-15);
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// Round trip: move each intrinsic parameter a little, re-project / re-undistort, and compare
// with the analytic Jacobians.
TEST(CameraModelTest, IntrinsicsJacobiansMatchFiniteDifferences) {
  const CameraIntrinsics k = testing::WideAnglePaperCamera();
  const double steps[kNumIntrinsicParams] = {1e-3, 1e-3, 1e-3, 1e-3, 1e-7, 1e-7, 1e-8, 1e-8, 1e-7};
  const Eigen::Vector2d pixels[] = {{100, 80}, {640, 500}, {1200, 950}};
  for (const auto& px : pixels) {
    Eigen::Matrix2d n_from_px;
    const auto n = PixelToNormalized(k, px, &n_from_px);
    ASSERT_TRUE(n);
    const auto j_pixel = PixelJacobianWrtIntrinsics(k, *n);
    const auto j_normalized = NormalizedJacobianWrtIntrinsics(k, *n, n_from_px);
    for (int p = 0; p < kNumIntrinsicParams; ++p) {
      Eigen::Matrix<double, kNumIntrinsicParams, 1> delta =
          Eigen::Matrix<double, kNumIntrinsicParams, 1>::Zero();
      delta[p] = steps[p];
      const auto plus = PerturbIntrinsics(k, delta), minus = PerturbIntrinsics(k, -delta);
      const Eigen::Vector2d d_pixel =
          (NormalizedToPixel(plus, *n) - NormalizedToPixel(minus, *n)) / (2 * steps[p]);
      EXPECT_NEAR((d_pixel - j_pixel.col(p)).norm(), 0, 1e-5 * (1 + d_pixel.norm()))
          << kIntrinsicParamNames[p] << " at " << px.transpose();
      const Eigen::Vector2d d_normalized =
          (*PixelToNormalized(plus, px) - *PixelToNormalized(minus, px)) / (2 * steps[p]);
      EXPECT_NEAR((d_normalized - j_normalized.col(p)).norm(), 0, 1e-5 * (1 + d_normalized.norm()))
          << kIntrinsicParamNames[p] << " at " << px.transpose();
    }
  }
}

}  // namespace
}  // namespace monocle
