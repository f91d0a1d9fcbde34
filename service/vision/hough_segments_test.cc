#include "service/vision/hough_segments.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "service/vision/edge_test_images.h"

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<EdgePixel> EdgesOf(const cv::Mat& grey) {
  cv::Mat smooth;
  cv::GaussianBlur(grey, smooth, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REPLICATE);
  auto edges = ThinEdges(smooth, CornerDetectorOptions{});
  for (auto& e : edges) e.angle = std::atan2(e.ny, e.nx);  // as the detector sets it
  return edges;
}

// The strongest peak is the step's line: its normal's angle and its distance from the origin.
TEST(HoughSegmentsTest, TheStrongestPeakIsTheStepsLine) {
  for (double angle_deg : {30.0, 75.0, 120.0}) {
    const double angle = angle_deg * kPi / 180;
    const double rho = 70 + 40 * std::sin(angle);
    const cv::Mat grey = testing::HalfPlaneStep(200, 160, angle, rho, 70, 150, 0.8, 2.0, 5);
    const auto edges = EdgesOf(grey);
    const auto peaks = HoughPeaks(edges, 250, 200, 30, 8);
    ASSERT_FALSE(peaks.empty()) << angle_deg;
    const double peak_angle = peaks[0].angle_bin * kPi / kAngleBins;
    EXPECT_NEAR(peak_angle * 180 / kPi, angle_deg, 1.0);
    EXPECT_NEAR(peaks[0].rho_bin, rho, 1.5) << angle_deg;
    for (size_t i = 1; i < peaks.size(); ++i) EXPECT_LE(peaks[i].votes, peaks[0].votes);
  }
}

// The edges on a peak's line make one segment along it, as long as the line is in view.
TEST(HoughSegmentsTest, AStepsEdgesMakeOneSegmentAsLongAsTheLineInView) {
  const double angle = 30 * kPi / 180, rho = 90;
  const cv::Mat grey = testing::HalfPlaneStep(200, 160, angle, rho, 70, 150, 0.8, 2.0, 6);
  const auto edges = EdgesOf(grey);
  std::vector<const EdgePixel*> all;
  for (const auto& e : edges) all.push_back(&e);
  std::vector<Segment> segments;
  SegmentsOfLine(all, 7, angle, rho, 40, &segments);
  ASSERT_EQ(segments.size(), 1u);
  const Segment& s = segments[0];
  EXPECT_EQ(s.line, 7);
  EXPECT_NEAR(std::abs(s.normal.dot(Eigen::Vector2d(std::cos(angle), std::sin(angle)))), 1, 1e-3);
  EXPECT_NEAR(std::abs(s.rho), rho, 1.0);
  // The line is in view from (103.9, 0) to (11.5, 160): 184.7 px, less a pixel or two at
  // each border where no gradient is taken.
  const double length = std::abs(s.t1 - s.t0);
  EXPECT_GT(length, 170);
  EXPECT_LT(length, 186);
  EXPECT_GT(s.support, 100);
}

// Too short a run of edges is not a segment.
TEST(HoughSegmentsTest, ARunShorterThanTheMinimumIsNoSegment) {
  const double angle = 30 * kPi / 180, rho = 90;
  const cv::Mat grey = testing::HalfPlaneStep(200, 160, angle, rho, 70, 150, 0.8, 2.0, 7);
  const auto edges = EdgesOf(grey);
  std::vector<const EdgePixel*> all;
  for (const auto& e : edges) all.push_back(&e);
  std::vector<Segment> segments;
  SegmentsOfLine(all, 0, angle, rho, 400, &segments);
  EXPECT_TRUE(segments.empty());
}

}  // namespace
}  // namespace monocle::corner_detection
