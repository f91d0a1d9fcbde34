#include "service/vision/edge_line_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace monocle {
namespace {

// Points along y = 0.3 x + 0.1 (normalized units), with noise across the line.
struct NoisyLine {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> steps;
};
NoisyLine PointsOnLine(int n, double sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  const Eigen::Vector2d direction = Eigen::Vector2d(1, 0.3).normalized();
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  NoisyLine line;
  for (int i = 0; i < n; ++i) {
    line.points.push_back(Eigen::Vector2d(0, 0.1) + (i * 0.01) * direction + noise(rng) * normal);
    line.steps.push_back(30);
  }
  return line;
}

double AngleToTruth(const LineFit& fit) {
  const Eigen::Vector2d truth = Eigen::Vector2d(1, 0.3).normalized();
  return std::acos(std::min(1.0, std::abs(fit.direction.dot(truth))));
}

TEST(EdgeLineFitTest, FitsTheLineThroughNoisyPoints) {
  const auto line = PointsOnLine(100, 1e-4, 1);
  const auto fit = RobustLineFit(line.points, line.steps, 1e-6);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT(AngleToTruth(*fit), 1e-3);
  EXPECT_GE(fit->inliers.size(), 98u) << "3-sigma rejection keeps nearly every point";
  EXPECT_NEAR(fit->normal_rms, 1e-4, 3e-5);
}

// Clutter crossing the edge (a tenth of the points, far off the line) is rejected.
TEST(EdgeLineFitTest, RejectsPointsFarOffTheLine) {
  auto line = PointsOnLine(100, 1e-4, 2);
  for (int i = 0; i < 100; i += 10) line.points[i].y() += 0.05;
  const auto fit = RobustLineFit(line.points, line.steps, 1e-6);
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT(AngleToTruth(*fit), 1e-3);
  EXPECT_LE(fit->inliers.size(), 90u) << "every point off the line is rejected";
  EXPECT_GE(fit->inliers.size(), 88u);
}

// A point on a weak step counts less: its noise across the edge is larger.
TEST(EdgeLineFitTest, WeighsEachPointByItsContrast) {
  auto line = PointsOnLine(40, 1e-4, 3);
  line.steps[10] = 5;  // (5 / 30)^2 is under the 1/4 floor
  const auto fit = RobustLineFit(line.points, line.steps, 1e-6);
  ASSERT_TRUE(fit.has_value());
  EXPECT_DOUBLE_EQ(fit->inlier_weights[10], 0.25);
  EXPECT_DOUBLE_EQ(fit->inlier_weights[11], 1.0);
}

TEST(EdgeLineFitTest, TooFewPointsGiveNoLine) {
  const auto line = PointsOnLine(4, 1e-4, 4);
  EXPECT_FALSE(RobustLineFit(line.points, line.steps, 1e-6).has_value());
}

LineFit Through(const Eigen::Vector2d& point, double heading_rad) {
  LineFit f;
  f.centroid = point;
  f.direction = Eigen::Vector2d(std::cos(heading_rad), std::sin(heading_rad));
  return f;
}

TEST(EdgeLineFitTest, IntersectionsAndTheCornerOfThreeLines) {
  const Eigen::Vector2d corner(0.2, -0.1);
  const LineFit a = Through(corner + Eigen::Vector2d(0.3, 0), 0);
  const LineFit b = Through(corner + 0.1 * Eigen::Vector2d(std::cos(2.1), std::sin(2.1)), 2.1);
  const LineFit c = Through(corner + 0.2 * Eigen::Vector2d(std::cos(4.2), std::sin(4.2)), 4.2);
  const auto ab = IntersectLines(a, b);
  ASSERT_TRUE(ab.has_value());
  EXPECT_LT((*ab - corner).norm(), 1e-12);
  EXPECT_FALSE(IntersectLines(a, Through({0, 1}, 0)).has_value()) << "parallel lines";
  const auto found = ConstrainedCorner({a, b, c});
  ASSERT_TRUE(found.has_value());
  EXPECT_LT((*found - corner).norm(), 1e-12);
}

// Points beyond a gap in the edge tell less about its direction than their number says.
TEST(EdgeLineFitTest, PointsBeyondAGapLoseLeverage) {
  LineFit fit = Through({0, 0}, 0);
  for (int i = 0; i < 20; ++i) fit.inliers.push_back({i * 0.002, 0});  // every 2 px at f 1000
  EXPECT_DOUBLE_EQ(BeyondGapLeverage(fit, {0, 0}, 1000, MaxGapPx(2)), 1.0);
  for (int i = 0; i < 10; ++i) fit.inliers.push_back({0.3 + i * 0.002, 0});  // after 260 px
  EXPECT_GT(BeyondGapLeverage(fit, {0, 0}, 1000, MaxGapPx(2)), 2.0);
}

}  // namespace
}  // namespace monocle
