#include "service/vision/edge_tracing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "service/vision/edge_test_images.h"

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

// From a point on a blurred step, the trace follows the edge to the image's border, every
// point on the true line to a fraction of a pixel.
TEST(EdgeTracingTest, TheTraceFollowsTheEdgeToTheBorder) {
  const double angle = 100 * kPi / 180, rho = 120;  // a nearly horizontal edge
  const cv::Mat grey = testing::HalfPlaneStep(400, 300, angle, rho, 90, 150, 1.2, 2.0, 11);
  const Eigen::Vector2d normal(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());      // towards +x
  const Eigen::Vector2d start = rho * normal + 120 * along;  // on the line, at (97.4, 139)
  // A direction a degree off, as the Hough stage gives it: the trace refits as it goes.
  const double off = kPi / 180;
  const Eigen::Vector2d direction(std::cos(off) * along.x() - std::sin(off) * along.y(),
                                  std::sin(off) * along.x() + std::cos(off) * along.y());
  const auto points = TraceEdge(grey, start, direction, 10, 4);
  ASSERT_GT(points.size(), 30u);
  double furthest = 0;
  for (const auto& p : points) {
    EXPECT_NEAR(p.point_px.dot(normal), rho, 0.3) << p.point_px.transpose();
    furthest = std::max(furthest, (p.point_px - start).dot(along));
  }
  // The line leaves the image at x = 399 (it is 10 degrees off horizontal).
  const double to_border = (399 - start.x()) / along.x();
  EXPECT_GT(furthest, to_border - 20);
}

TEST(EdgeTracingTest, ClippedSurfacesAreSeen) {
  const cv::Mat clipped = testing::HalfPlaneStep(200, 160, 0, 100, 120, 255, 1.0, 0, 0);
  const cv::Mat unclipped = testing::HalfPlaneStep(200, 160, 0, 100, 120, 200, 1.0, 0, 0);
  const Eigen::Vector2d on_edge(100, 80), across(1, 0);
  EXPECT_TRUE(ClippedAcross(clipped, on_edge, across));
  EXPECT_FALSE(ClippedAcross(unclipped, on_edge, across));
  EXPECT_TRUE(ClippedAlong(clipped, {100, 20}, {100, 140}));
  EXPECT_FALSE(ClippedAlong(unclipped, {100, 20}, {100, 140}));
  const cv::Mat glare(160, 200, CV_8U, cv::Scalar(255)), grey(160, 200, CV_8U, cv::Scalar(128));
  EXPECT_TRUE(SaturatedAround(glare, {100, 80}));
  EXPECT_FALSE(SaturatedAround(grey, {100, 80}));
}

}  // namespace
}  // namespace monocle::corner_detection
