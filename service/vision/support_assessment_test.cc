#include "service/vision/support_assessment.h"

#include <gtest/gtest.h>

#include <numbers>

namespace monocle {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics k;
  k.width_px = 1280;
  k.height_px = 1024;
  k.fx = k.fy = 1600;
  k.cx = 640;
  k.cy = 512;
  return k;
}

// The demo's first view: a corner ahead and above, every edge long in the image.
CornerPose Pose() {
  CornerPose p;
  p.x_m = 2.0;
  p.y_m = 1.5;
  p.z_m = 1.6;
  p.pan_rad = 2.2143;
  p.tilt_rad = 0.9;
  p.swing_rad = 0.1;
  return p;
}

// A located corner whose edges are the pose's own lines: points every 2 px from 8 px off the
// corner to where each leaves the image, `step_grey` across each, `offset_px` across the
// line of edge `shifted` (-1: none).
struct Scene {
  std::array<LineFit, 3> fits;
  CornerLocation location;
  Eigen::Vector2d corner_n;
};
Scene MakeScene(const std::array<double, 3>& step_grey, int shifted = -1, double offset_px = 0) {
  const CameraIntrinsics k = Camera();
  Scene scene;
  CornerLocation& out = scene.location;
  out.pose = Pose();
  out.covariance = Eigen::Matrix<double, 5, 5>::Identity() * 1e-8;  // precise: no imprecision
  out.noise_sigma_grey = 2;
  const Eigen::Vector3d c = CornerToCamera(out.pose, Eigen::Vector3d::Zero());
  scene.corner_n = c.head<2>() / c.z();
  out.corner_px = NormalizedToPixel(k, scene.corner_n);
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d a = CornerToCamera(out.pose, 1e-3 * Eigen::Vector3d::Unit(axis));
    const Eigen::Vector2d dir = (a.head<2>() / a.z() - scene.corner_n).normalized();
    const Eigen::Vector2d normal(-dir.y(), dir.x());
    std::vector<Eigen::Vector2d> points;
    for (double s = 8; s < 3000; s += 2) {
      const Eigen::Vector2d n = scene.corner_n + s / k.fx * dir;
      const Eigen::Vector2d px = NormalizedToPixel(k, n);
      if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px - 1 || px.y() > k.height_px - 1) break;
      points.push_back(n + (axis == shifted ? offset_px / k.fx : 0.0) * normal);
    }
    auto fit =
        RobustLineFit(points, std::vector<double>(points.size(), step_grey[axis]), 0.05 / k.fx);
    EXPECT_TRUE(fit.has_value());
    scene.fits[axis] = *fit;
  }
  return scene;
}

CornerLocation Assess(Scene scene) {
  const cv::Mat flat(1024, 1280, CV_8UC1, cv::Scalar(128));
  AssessSupport(flat, Camera(), scene.fits, {0, 1, 2}, scene.corner_n, CornerQualityOptions{},
                {2, 2, 2}, &scene.location);
  return scene.location;
}

TEST(SupportAssessmentTest, EdgesOnThePosesLinesSupportIt) {
  const CornerLocation out = Assess(MakeScene({20, 20, 40}));
  EXPECT_FALSE(out.suspect) << out.suspect_reason;
  for (int axis = 0; axis < 3; ++axis) {
    const EdgeSupport& s = out.support[axis];
    EXPECT_NEAR(s.misfit_px, 0, 0.05) << axis;
    EXPECT_GT(s.coverage, 0.95) << axis;
    // The visible length is found in steps 2 % apart along the axis.
    EXPECT_NEAR(s.length_px, s.visible_length_px, 0.02 * s.visible_length_px + 2) << axis;
    EXPECT_GT(s.length_px, 200) << axis;
    EXPECT_DOUBLE_EQ(s.contrast_to_noise, s.contrast_grey / 2);
  }
  EXPECT_DOUBLE_EQ(out.support[2].contrast_grey, 40);
}

TEST(SupportAssessmentTest, AnEdgeOffThePosesLineIsNamed) {
  const CornerLocation out = Assess(MakeScene({20, 20, 40}, 1, 3.0));
  EXPECT_TRUE(out.suspect);
  EXPECT_FALSE(out.suspect_only_imprecise);
  EXPECT_NEAR(out.support[1].misfit_px, 3.0, 0.1);
  EXPECT_NE(out.suspect_reason.find("edge Y lies 3.00 px off the pose's line"), std::string::npos)
      << out.suspect_reason;
}

// At a ceiling corner one edge's step equals the other two's (the three surfaces' levels).
TEST(SupportAssessmentTest, StepsThatDoNotAddUpAreNamed) {
  const CornerLocation out = Assess(MakeScene({20, 20, 80}));
  EXPECT_TRUE(out.suspect);
  EXPECT_NE(out.suspect_reason.find("the edges' steps do not add up"), std::string::npos)
      << out.suspect_reason;
}

TEST(SupportAssessmentTest, AnEdgeBelowTheNoiseIsNamed) {
  const CornerLocation out = Assess(MakeScene({1.5, 20, 20}));
  EXPECT_TRUE(out.suspect);
  EXPECT_NE(out.suspect_reason.find("edge X contrast 1.5 grey levels at noise 2.0"),
            std::string::npos)
      << out.suspect_reason;
}

// A pose known no better than its 1 sigma allows is suspect for that alone, and says which
// edge limits it.
TEST(SupportAssessmentTest, AnImprecisePoseSaysWhichEdgeLimitsIt) {
  Scene scene = MakeScene({20, 20, 40});
  scene.location.covariance(0, 0) = scene.location.covariance(1, 1) = 0.05 * 0.05;
  scene.location.support[2].position_variance_share = 0.8;
  const CornerLocation out = Assess(scene);
  EXPECT_TRUE(out.suspect);
  EXPECT_TRUE(out.suspect_only_imprecise);
  EXPECT_TRUE(IsImprecisionReason(out.suspect_reason)) << out.suspect_reason;
  EXPECT_NE(out.suspect_reason.find("80 % of its variance from edge Z"), std::string::npos)
      << out.suspect_reason;
}

}  // namespace
}  // namespace monocle
