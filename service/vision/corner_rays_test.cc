#include "service/vision/corner_rays.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace monocle {
namespace {

constexpr double kPi = std::numbers::pi;
const Eigen::Vector2d kCorner(300.3, 240.6);

Eigen::Vector2d Direction(double deg) {
  return {std::cos(deg * kPi / 180), std::sin(deg * kPi / 180)};
}

// Sectors around kCorner: sector i spans image angles [boundary_deg[i], boundary_deg[i+1])
// (the last wraps to the first) and has grey[i]; blurred like a lens and with sensor noise.
cv::Mat Sectors(const std::vector<double>& boundary_deg, const std::vector<double>& grey,
                double noise_sigma = 2, double glare_per_px = 0,
                const Eigen::Vector2d& corner = kCorner) {
  cv::Mat image(480, 640, CV_32F);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      double a = std::atan2(y - corner.y(), x - corner.x()) * 180 / kPi;
      size_t sector = boundary_deg.size() - 1;
      for (size_t i = 0; i + 1 < boundary_deg.size(); ++i)
        if (a >= boundary_deg[i] && a < boundary_deg[i + 1]) sector = i;
      image.at<float>(y, x) = static_cast<float>(grey[sector] + glare_per_px * x);
    }
  }
  cv::GaussianBlur(image, image, cv::Size(0, 0), 1.2);
  cv::Mat noise(image.size(), CV_32F);
  cv::theRNG().state = 12345;
  cv::randn(noise, 0, noise_sigma);
  cv::Mat out;
  cv::Mat noisy = image + noise;
  noisy.convertTo(out, CV_8U);
  return out;
}

const std::array<Eigen::Vector2d, 3> kY = {Direction(-150), Direction(-30), Direction(90)};

TEST(CornerRaysTest, AYAloneHasNoOtherRayAndItsEdgesStepsAreMeasured) {
  // Ceiling 200 above (between -150 and -30 degrees), walls 170 and 150 below.
  const cv::Mat image = Sectors({-150, -30, 90}, {200, 170, 150});
  const OtherRay ray = StrongestOtherRay(image, kCorner, kY);
  EXPECT_NEAR(ray.edge_step_grey[0], 50, 3);  // 200 | 150
  EXPECT_NEAR(ray.edge_step_grey[1], 30, 3);  // 200 | 170
  EXPECT_NEAR(ray.edge_step_grey[2], 20, 3);  // 170 | 150
  EXPECT_LT(ray.step_grey, 2);
}

TEST(CornerRaysTest, AFourthEdgeIsFoundWithItsStepAndDirection) {
  // A fourth surface between -90 and -30 degrees: a ray at -90 with a step of 40.
  const cv::Mat image = Sectors({-150, -90, -30, 90}, {200, 160, 170, 150});
  const OtherRay ray = StrongestOtherRay(image, kCorner, kY);
  EXPECT_NEAR(ray.step_grey, 40, 3);
  EXPECT_NEAR(ray.angle_rad * 180 / kPi, -90, 1);
}

// Rings from 1 px out: those too small for their step windows (a few samples round) are not
// read, and the rest find the fourth edge as the default rings do. (Read, the 1 px ring's
// windows reach outside its samples: AddressSanitizer reports it.)
TEST(CornerRaysTest, RingsTooSmallForTheirWindowsAreNotRead) {
  const cv::Mat image = Sectors({-150, -90, -30, 90}, {200, 160, 170, 150});
  RayProfileOptions from_the_corner;
  from_the_corner.min_radius_px = 1;
  from_the_corner.radius_step_px = 3;
  const OtherRay ray = StrongestOtherRay(image, kCorner, kY, from_the_corner);
  EXPECT_NEAR(ray.step_grey, 40, 3);
  EXPECT_NEAR(ray.angle_rad * 180 / kPi, -90, 1);
}

// Where each ring's samples wrap round (image angle 0, approached from below), its step
// windows reach across the wrap: a ray just below 0 degrees is read as any other.
TEST(CornerRaysTest, ARayWhereTheRingsWrapIsFoundWithItsStep) {
  for (const double angle : {-6.0, -2.0, 3.0}) {
    const cv::Mat image = Sectors({-150, -30, angle, 90}, {200, 170, 130, 150});
    const OtherRay ray = StrongestOtherRay(image, kCorner, kY);
    EXPECT_NEAR(ray.step_grey, 40, 3) << "at " << angle << " degrees";
    EXPECT_NEAR(ray.angle_rad * 180 / kPi, angle, 1);
  }
}

TEST(CornerRaysTest, ALineThatMissesTheCornerIsNotARay) {
  cv::Mat image = Sectors({-150, -30, 90}, {200, 170, 150});
  // A dark cable 25 px from the corner, across the ceiling, and a picture frame's edge.
  cv::line(image, cv::Point(200, 190), cv::Point(420, 230), cv::Scalar(60), 3);
  cv::rectangle(image, cv::Rect(330, 260, 80, 60), cv::Scalar(90), cv::FILLED);
  const OtherRay ray = StrongestOtherRay(image, kCorner, kY);
  EXPECT_LT(ray.step_grey, 6) << "at " << ray.angle_rad * 180 / kPi << " degrees";
}

TEST(CornerRaysTest, GlareAcrossTheCornerIsNotARay) {
  // Brightening 0.3 grey levels per pixel across the image: 90 over its width.
  const cv::Mat image = Sectors({-150, -30, 90}, {150, 120, 100}, 2, 0.3);
  const OtherRay ray = StrongestOtherRay(image, kCorner, kY);
  EXPECT_LT(ray.step_grey, 4);
  // The vertical edge's step takes in the glare between its two windows, ~9 px apart.
  EXPECT_NEAR(ray.edge_step_grey[2], 20 + 0.3 * 9, 2);
}

TEST(CornerRaysTest, RingsOutsideTheImageAreNotRead) {
  // The corner 10 px from the left border, one edge running left out of the image at once:
  // its step cannot be read (0); the others', and a fourth ray's, can.
  const Eigen::Vector2d near_border(10.5, 240.6);
  const std::array<Eigen::Vector2d, 3> y = {Direction(180), Direction(-45), Direction(45)};
  const cv::Mat image = Sectors({-180, -45, 0, 45}, {200, 150, 120, 170}, 2, 0, near_border);
  const OtherRay ray = StrongestOtherRay(image, near_border, y);
  EXPECT_EQ(ray.edge_step_grey[0], 0);
  EXPECT_NEAR(ray.edge_step_grey[1], 50, 3);
  EXPECT_NEAR(ray.edge_step_grey[2], 50, 3);
  EXPECT_NEAR(ray.step_grey, 30, 3);
  EXPECT_NEAR(ray.angle_rad, 0, 0.02);
}

TEST(CornerRaysTest, ACornerFarOutsideTheImageReadsNothing) {
  const cv::Mat image = Sectors({-150, -30, 90}, {200, 170, 150});
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(-500, 240), Eigen::Vector2d(300, 1e30),
                                        Eigen::Vector2d(std::nan(""), 240)}) {
    const OtherRay ray = StrongestOtherRay(image, corner, kY);
    EXPECT_EQ(ray.step_grey, 0);
    EXPECT_EQ(ray.edge_step_grey[0] + ray.edge_step_grey[1] + ray.edge_step_grey[2], 0);
  }
}

}  // namespace
}  // namespace monocle
