// The renderers' reference camera against the measurement code it must not share: the same
// points projected by OpenCV (cv::projectPoints) with the paper's eq. (1) rotation and by
// service/geometry, pixel centres, and the roll and pitch conventions checked by physical
// facts rather than by either implementation.
#include "camera/render/reference_camera.h"

#include <gtest/gtest.h>

#include <random>

#include "camera/render/floor_renderer.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/floor_model.h"
#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::Deg;

TEST(ReferenceCameraTest, CornerProjectionAgreesWithTheGeometryCode) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const auto pose = testing::RandomCornerPose(rng, k);
    ASSERT_TRUE(pose);
    const Eigen::Matrix3d r = reference::RotationCameraFromCorner(*pose);
    EXPECT_LT((r - RotationCameraFromCorner(*pose)).norm(), 1e-12) << *pose;
    const Eigen::Vector3d c(pose->x_m, pose->y_m, pose->z_m);
    // Points on the three edges, projected by OpenCV and by our camera model.
    std::vector<Eigen::Vector3d> points;
    for (int axis = 0; axis < 3; ++axis)
      for (double t : {0.0, 0.3, 1.0}) points.push_back(t * Eigen::Vector3d::Unit(axis));
    const auto opencv = reference::ProjectPoints(k, r, -r * c, points);
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d p = CornerToCamera(*pose, points[i]);
      if (p.z() <= 0.1) continue;
      const Eigen::Vector2d ours = ProjectToPixel(k, p);
      EXPECT_NEAR(opencv[i].x, ours.x(), 1e-6);
      EXPECT_NEAR(opencv[i].y, ours.y(), 1e-6);
    }
  }
}

TEST(ReferenceCameraTest, PaperSwingAndTiltMeanWhatTheyShouldInTheRoom) {
  // Tilt 0 looks straight up (optical axis = -Z of the corner frame, Z points down); tilt
  // 90 degrees with pan 0 looks level along +Y. Swing 0 is upright: the image's "down"
  // (camera +y) points down in the room (+Z) when the camera looks level.
  const Eigen::Matrix3d up = reference::RotationCameraFromCorner({1, 1, 1, 0, 0, 0});
  EXPECT_LT((up.row(2).transpose() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  const Eigen::Matrix3d level = reference::RotationCameraFromCorner({1, 1, 1, 0, Deg(90), 0});
  EXPECT_LT((level.row(2).transpose() - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  EXPECT_GT(level.row(1).dot(Eigen::Vector3d::UnitZ()), 0.999);
}

TEST(ReferenceCameraTest, UndistortionAgreesWithTheGeometryCodeAndPixelCentresAreIntegers) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::vector<cv::Point2d> pixels;
  for (double v = 0; v < k.height_px; v += 97.5)
    for (double u = 0; u < k.width_px; u += 101.25) pixels.emplace_back(u, v);
  const auto normalized = reference::UndistortPixels(k, pixels);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const auto ours = PixelToNormalized(k, Eigen::Vector2d(pixels[i].x, pixels[i].y));
    ASSERT_TRUE(ours);
    EXPECT_NEAR(normalized[i].x, ours->x(), 1e-9);
    EXPECT_NEAR(normalized[i].y, ours->y(), 1e-9);
  }
  // The principal point's pixel maps to the optical axis: pixel centres sit at integers.
  CameraIntrinsics pinhole = k;
  pinhole.distortion = {};
  pinhole.cx = 640;
  pinhole.cy = 512;
  const cv::Mat grid = reference::UndistortedPixelGrid(pinhole);
  EXPECT_NEAR(grid.at<cv::Point2d>(512, 640).x, 0, 1e-12);
  EXPECT_NEAR(grid.at<cv::Point2d>(512, 640).y, 0, 1e-12);
  EXPECT_NEAR(grid.at<cv::Point2d>(512, 641).x, 1 / pinhole.fx, 1e-12);
}

TEST(ReferenceCameraTest, FloorRollAndPitchFollowThePhysicalConventions) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 100; ++trial) {
    const FloorPose pose = testing::RandomFloorPose(rng);
    EXPECT_LT((reference::RotationCameraFromRobot(pose) - RotationCameraFromRobot(pose)).norm(),
              1e-12);
  }
  // Pitch 90 degrees, no roll: the camera looks level, straight ahead (+Y_w), image down is
  // world down.
  const Eigen::Matrix3d level = reference::RotationCameraFromRobot({1.0, Deg(90), 0, 0});
  EXPECT_LT((level.row(2).transpose() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((level.row(1).transpose() + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  // Positive roll turns the image content from +x towards +y (clockwise on the screen, y
  // down): a floor point right of the optical axis moves down in the image.
  const CameraIntrinsics k = testing::PaperCamera();
  const Eigen::Vector3d right_ahead(0.5, 2.0, 0.0);
  auto pixel = [&](double roll) {
    const FloorPose p{1.0, Deg(120), 0, roll};
    const Eigen::Matrix3d r = reference::RotationCameraFromRobot(p);
    const Eigen::Vector3d t = -r * Eigen::Vector3d(0, 0, p.height_m);
    return reference::ProjectPoints(k, r, t, {right_ahead})[0];
  };
  const auto level_px = pixel(0), rolled_px = pixel(Deg(5));
  EXPECT_GT(rolled_px.y, level_px.y + 5);
  // And our measurement code inverts the reference projection exactly.
  const FloorPose p{1.0, Deg(120), 0, Deg(5)};
  const auto floor = FloorPointFromPixel(k, p, Eigen::Vector2d(rolled_px.x, rolled_px.y));
  ASSERT_TRUE(floor.ok());
  EXPECT_LT((*floor - right_ahead).norm(), 1e-6);
}

}  // namespace
}  // namespace monocle
