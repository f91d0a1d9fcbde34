#include "service/vision/corner_locator.h"

#include <gtest/gtest.h>

#include <iostream>

#include "camera/render/corner_renderer.h"
#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::Deg;

struct Case {
  const char* name;
  CornerPose pose;
  bool distortion, clutter, lighting;
};

class CornerLocatorTest : public ::testing::TestWithParam<Case> {};

TEST_P(CornerLocatorTest, RecoversTheRenderedPose) {
  const Case& c = GetParam();
  CameraIntrinsics k = testing::PaperCamera();
  if (!c.distortion) k.distortion = {};
  CornerScene scene;
  scene.noise_sigma = 2;
  scene.clutter = c.clutter;
  scene.uneven_lighting = c.lighting;
  const auto got = LocateCorner(RenderCornerScene(k, c.pose, scene), k, c.pose.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  const double distance = std::hypot(c.pose.x_m, c.pose.y_m);
  EXPECT_LT(std::hypot(got->pose.x_m - c.pose.x_m, got->pose.y_m - c.pose.y_m), 0.005 * distance)
      << *got;
  EXPECT_NEAR(got->pose.tilt_rad, c.pose.tilt_rad, Deg(0.1)) << *got;
  EXPECT_NEAR(got->pose.pan_rad, c.pose.pan_rad, Deg(0.2)) << *got;
  EXPECT_NEAR(got->pose.swing_rad, c.pose.swing_rad, Deg(0.2)) << *got;
  EXPECT_LT(got->rms_px, 0.5);
  // The quaternion is the same orientation as pan, tilt and swing.
  const Eigen::Matrix3d r = RotationCameraFromCorner(got->pose).transpose();
  EXPECT_LT((got->q_corner_camera.toRotationMatrix() - r).norm(), 1e-9);
  // The reported corner pixel is where the true corner projects.
  const Eigen::Vector3d p = CornerToCamera(c.pose, Eigen::Vector3d::Zero());
  EXPECT_LT((got->corner_px - NormalizedToPixel(k, p.head<2>() / p.z())).norm(), 1.0);
}

INSTANTIATE_TEST_SUITE_P(
    Views, CornerLocatorTest,
    ::testing::Values(
        Case{"Plain", {2.0, 1.5, 1.6, std::atan2(2.0, -1.5), 0.9, 0.1}, false, false, false},
        Case{
            "LensDistortion", {2.0, 1.5, 1.6, std::atan2(2.0, -1.5), 0.9, 0.1}, true, false, false},
        Case{"ClutterAndUnevenLighting",
             {2.0, 1.5, 1.6, std::atan2(2.0, -1.5), 0.9, 0.1},
             true,
             true,
             true},
        // Corner about 100 px from the left border.
        Case{"NearTheBorder",
             {1.43288, 1.90922, 1.42722, 2.87685, 1.00151, 0.214452},
             true,
             false,
             false},
        Case{"FarAndLevel",
             {5.0, 4.0, 1.2, std::atan2(5.0, -4.0), Deg(80), Deg(-10)},
             true,
             false,
             false},
        Case{"CloseAndSteep",
             {0.5, 0.6, 2.5, std::atan2(0.5, -0.6), Deg(15), Deg(20)},
             true,
             false,
             false}),
    [](const auto& info) { return info.param.name; });

TEST(CornerLocatorRoomTest, AWallEdgeFadedNearTheCornerStillMakesTheY) {
  // A near-level view (tilt 84 degrees) where the lamp and the shading make both walls 230
  // grey at the ceiling corner: the wall-wall edge is invisible for its first 120 px and
  // its Hough segment starts that far from the corner. The floor corner at the other end of
  // that edge is a perfect Y too (a floor corner is a ceiling corner turned over; no
  // geometry tells them apart), and it was taken: 56 % off and not flagged. The ceiling
  // corner's Y must be found despite the gap.
  const auto k = testing::PaperCamera();
  const CornerPose truth{2.62322, 5.44165, 1.30491, 2.82104, 1.46787, -0.433534};
  CornerScene scene;
  scene.seed = 8070;
  scene.room_height_m = truth.z_m + 1.2;
  scene.realistic = RandomRealisticLook(scene.seed, k);
  const auto got = LocateCorner(RenderCornerScene(k, truth, scene), k, truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_LT(std::hypot(got->pose.x_m - truth.x_m, got->pose.y_m - truth.y_m),
            0.01 * std::hypot(truth.x_m, truth.y_m))
      << *got;
  EXPECT_NEAR(got->pose.swing_rad, truth.swing_rad, Deg(0.5)) << *got;
}

// A raw camera frame and the same frame as JPEG are judged alike. Compression removes most
// of the pixel-to-pixel noise but not what the edge measurement averages, so the noise
// reported (and each edge's contrast against it) is the sensor's in both. Judged against the
// pixel-to-pixel noise instead, the JPEG frame's noise read 1.3 for a sensor's 3.5 and the
// raw frame's faint wall-wall edge (6 grey levels) was flagged "contrast 6 at noise 3.5"
// while the compressed frame's was not.
TEST(CornerLocatorRoomTest, ARawFrameAndItsJpegAreJudgedAgainstTheSameNoise) {
  const auto k = testing::PaperCamera();
  const CornerPose pose{2.0, 1.5, 1.6, 2.2143, 0.9, 0.1};
  CornerScene scene;
  scene.seed = 12;
  RealisticLook look;
  look.ceiling_grey = 190;
  look.wall_x0_grey = 170;
  look.wall_y0_grey = 164;  // the wall-wall (Z) edge: 6 grey levels
  look.vignetting = 0.1;
  look.hotspot_gain = 0.05;
  look.blur_sigma_px = 1.2;
  look.noise_sigma = 3.5;
  std::array<double, 2> noise{};
  for (int jpeg_quality : {0, 80}) {
    look.jpeg_quality = jpeg_quality;
    scene.realistic = look;
    const auto got = LocateCorner(RenderCornerScene(k, pose, scene), k, pose.z_m);
    ASSERT_TRUE(got.ok()) << got.error().message;
    EXPECT_NEAR(got->noise_sigma_grey, look.noise_sigma, 0.25 * look.noise_sigma)
        << "JPEG quality " << jpeg_quality;
    noise[jpeg_quality == 0 ? 0 : 1] = got->noise_sigma_grey;
    EXPECT_FALSE(got->suspect) << "JPEG quality " << jpeg_quality << ": " << got->suspect_reason;
    EXPECT_NEAR(got->pose.x_m, pose.x_m, 0.02);
    EXPECT_NEAR(got->pose.y_m, pose.y_m, 0.02);
  }
  EXPECT_NEAR(noise[1], noise[0], 0.25 * noise[0]);
}

TEST(CornerLocatorErrorsTest, BlankImageHasNoCorner) {
  const auto k = testing::PaperCamera();
  const auto got = LocateCorner(cv::Mat(1024, 1280, CV_8UC1, cv::Scalar(128)), k, 1.6);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.error().code, ErrorCode::kNotFound);
  EXPECT_NE(got.error().message.find("no ceiling corner"), std::string::npos);
}

TEST(CornerLocatorErrorsTest, OnlyTwoEdgesInViewIsNoCorner) {
  // Looking along a ceiling edge away from the corner: one edge and a wall, no Y.
  const auto k = testing::PaperCamera();
  const CornerPose pose{3.0, 1.0, 1.6, 1.9, 0.7, -0.2};
  const auto got = LocateCorner(RenderCornerScene(k, pose, CornerScene{}), k, 1.6);
  ASSERT_FALSE(got.ok());
  EXPECT_NE(got.error().message.find("no ceiling corner"), std::string::npos);
}

TEST(CornerLocatorErrorsTest, AWallPaintedLikeTheCeilingLeavesTwoEdgesAndSaysSo) {
  // The wall x = 0 exactly as bright as the ceiling: the Y edge between them vanishes; the X
  // and Z edges still meet at the corner. The error names what was seen, with numbers.
  const auto k = testing::PaperCamera();
  const CornerPose pose{2.0, 1.5, 1.6, 2.2143, 0.9, 0.1};
  CornerScene scene;
  scene.realistic = RandomRealisticLook(3, k);
  scene.realistic->wall_x0_grey = scene.realistic->ceiling_grey;
  scene.realistic->shading_per_m[0] = scene.realistic->shading_per_m[1] = Eigen::Vector2d::Zero();
  scene.realistic->shading_per_m[2] = Eigen::Vector2d::Zero();
  const auto got = LocateCorner(RenderCornerScene(k, pose, scene), k, 1.6);
  ASSERT_FALSE(got.ok()) << *got;
  const std::string& m = got.error().message;
  std::cout << m << "\n";
  EXPECT_NE(m.find("2 meet at"), std::string::npos) << m;
  EXPECT_NE(m.find("the third is too weak (contrast"), std::string::npos) << m;
  EXPECT_NE(m.find("grey levels at noise"), std::string::npos) << m;
}

TEST(CornerLocatorErrorsTest, AnOverexposedCeilingSaysSoAndLoweringTheExposureFixesIt) {
  // The ceiling brighter than the sensor's white: it clips at 255, and the blurred step cut
  // there would move the two ceiling edges by up to a pixel, so their points are refused.
  // The error must say why and what to do. The same view exposed 30 % lower is located.
  const auto k = testing::PaperCamera();
  const CornerPose pose{2.0, 1.5, 1.6, 2.2143, 0.9, 0.1};
  CornerScene scene;
  RealisticLook look;
  look.ceiling_grey = 300;
  look.wall_x0_grey = 200;
  look.wall_y0_grey = 185;
  look.hotspot_gain = 0;
  look.vignetting = 0;
  look.noise_sigma = 2;
  scene.realistic = look;
  const auto clipped = LocateCorner(RenderCornerScene(k, pose, scene), k, 1.6);
  ASSERT_FALSE(clipped.ok()) << *clipped;
  EXPECT_NE(clipped.error().message.find("saturated"), std::string::npos)
      << clipped.error().message;
  EXPECT_NE(clipped.error().message.find("lower the exposure"), std::string::npos)
      << clipped.error().message;

  for (double* grey : {&look.ceiling_grey, &look.wall_x0_grey, &look.wall_y0_grey}) *grey *= 0.7;
  scene.realistic = look;
  const auto exposed = LocateCorner(RenderCornerScene(k, pose, scene), k, 1.6);
  ASSERT_TRUE(exposed.ok()) << exposed.error().message;
  EXPECT_LT(std::hypot(exposed->pose.x_m - pose.x_m, exposed->pose.y_m - pose.y_m), 0.02);
}

TEST(CornerLocatorErrorsTest, TinyImageAndMissingDistanceAreClearErrors) {
  CameraIntrinsics k = testing::PaperCamera();
  k.width_px = k.height_px = 32;
  k.cx = k.cy = 16;
  const auto tiny = LocateCorner(cv::Mat(32, 32, CV_8UC1, cv::Scalar(0)), k, 1.6);
  ASSERT_FALSE(tiny.ok());
  EXPECT_NE(tiny.error().message.find("too small"), std::string::npos);
  const auto no_distance = LocateCorner(cv::Mat(32, 32, CV_8UC1, cv::Scalar(0)), k, 0);
  ASSERT_FALSE(no_distance.ok());
  EXPECT_NE(no_distance.error().message.find("ceiling"), std::string::npos);
  const auto wrong_size = LocateCorner(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), k, 1.6);
  ASSERT_FALSE(wrong_size.ok());
  EXPECT_NE(wrong_size.error().message.find("calibration is for 32x32"), std::string::npos);
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// Detection looks at a quarter of the resolution first and at half only when no Y found
// there is accepted: most views cost the quarter pass alone, none is lost to it.
TEST(CornerDetectionScaleTest, AQuarterFirstThenHalfWhenNothingThereIsAccepted) {
  const CameraIntrinsics k = testing::PaperCamera();
  const CornerPose pose{2.0, 1.5, 1.6, std::atan2(2.0, -1.5), 0.9, 0.1};
  CornerScene scene;
  scene.noise_sigma = 2;
  const cv::Mat image = RenderCornerScene(k, pose, scene);
  ASSERT_EQ(image.cols, 1280);

  const auto located = LocateCorner(image, k, pose.z_m);
  ASSERT_TRUE(located.ok()) << located.error();
  EXPECT_EQ(located->edges.detection_scale, 0.25) << "a plain view is found at a quarter";

  // Every Y offered at a quarter refused: the same image is searched again at half, and its
  // Y is the same corner.
  std::vector<double> offered_scales;
  std::optional<CornerEdges> at_half;
  const auto error = ForEachCornerCandidate(image, {}, &k, [&](CornerEdges edges) {
    offered_scales.push_back(edges.detection_scale);
    if (edges.detection_scale != 0.5) return false;
    at_half = std::move(edges);
    return true;
  });
  EXPECT_FALSE(error.has_value());
  ASSERT_TRUE(at_half.has_value());
  ASSERT_GE(offered_scales.size(), 2u);
  EXPECT_EQ(offered_scales.front(), 0.25);
  EXPECT_LT((at_half->corner_px - located->corner_px).norm(), 6.0);

  // Refusing everything: each resolution offered its Ys, and the reason names the last.
  int offered = 0;
  const auto refused = ForEachCornerCandidate(image, {}, &k, [&](CornerEdges) {
    ++offered;
    return false;
  });
  ASSERT_TRUE(refused.has_value());
  EXPECT_GE(offered, 2);
  EXPECT_NE(refused->message.find("no Y found is a ceiling corner"), std::string::npos)
      << refused->message;
}

// Images under 800 px on a side are searched at half resolution only (a quarter would
// leave too few pixels on a short edge).
TEST(CornerDetectionScaleTest, ASmallImageIsSearchedAtHalfOnly) {
  CameraIntrinsics k = testing::PaperCamera();
  k.width_px /= 2;
  k.height_px /= 2;
  k.fx /= 2;
  k.fy /= 2;
  k.cx = (k.cx + 0.5) / 2 - 0.5;
  k.cy = (k.cy + 0.5) / 2 - 0.5;
  const CornerPose pose{2.0, 1.5, 1.6, std::atan2(2.0, -1.5), 0.9, 0.1};
  CornerScene scene;
  scene.noise_sigma = 2;
  const cv::Mat image = RenderCornerScene(k, pose, scene);
  std::vector<double> offered_scales;
  (void)ForEachCornerCandidate(image, {}, &k, [&](CornerEdges edges) {
    offered_scales.push_back(edges.detection_scale);
    return false;
  });
  ASSERT_FALSE(offered_scales.empty());
  for (double s : offered_scales) EXPECT_EQ(s, 0.5);
}

}  // namespace
}  // namespace monocle
