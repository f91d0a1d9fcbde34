#include "service/vision/y_junctions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

// A segment from `gap` to `gap + length` pixels out of `corner` along `heading_deg`.
Segment Ray(const Eigen::Vector2d& corner, double heading_deg, double gap, double length,
            int line) {
  Segment s;
  s.line = line;
  const double a = heading_deg * kPi / 180;
  s.direction = Eigen::Vector2d(std::cos(a), std::sin(a));
  s.normal = Eigen::Vector2d(-s.direction.y(), s.direction.x());
  s.rho = s.normal.dot(corner);
  const double t_corner = s.direction.dot(corner);
  s.t0 = t_corner + gap;
  s.t1 = t_corner + gap + length;
  s.support = static_cast<int>(length);
  return s;
}

TEST(YJunctionsTest, AngleBetweenUnitVectors) {
  EXPECT_NEAR(AngleBetween({1, 0}, {0, 1}), kPi / 2, 1e-12);
  EXPECT_NEAR(AngleBetween({1, 0}, {-1, 0}), kPi, 1e-12);
  EXPECT_NEAR(AngleBetween({1, 0}, {1, 0}), 0, 1e-6);
}

// Three segments leaving one point 120 degrees apart are a Y, found at that point, with the
// three segments' directions pointing away from it.
TEST(YJunctionsTest, ThreeRaysFromOnePointAreAY) {
  const Eigen::Vector2d corner(100, 80);
  const std::vector<Segment> segments = {Ray(corner, 90, 3, 60, 0), Ray(corner, 210, 3, 70, 1),
                                         Ray(corner, 330, 3, 65, 2)};
  const auto found = FindYCandidates(segments, 200, 160, 4);
  ASSERT_FALSE(found.empty());
  EXPECT_LT((found[0].corner - corner).norm(), 1.0);
  std::array<bool, 3> used{};
  for (int i = 0; i < 3; ++i) used[found[0].segment[i]] = true;
  EXPECT_TRUE(used[0] && used[1] && used[2]);
  for (int i = 0; i < 3; ++i) {
    const Segment& s = segments[found[0].segment[i]];
    EXPECT_GT(found[0].direction[i].dot(s.End(1) - corner), 0) << "points away from the corner";
  }
}

// A fan (rays 60 degrees apart) is no ceiling corner: some angle is under 80 degrees.
TEST(YJunctionsTest, AFanOfRaysIsNoY) {
  const Eigen::Vector2d corner(100, 80);
  const std::vector<Segment> segments = {Ray(corner, 0, 3, 60, 0), Ray(corner, 60, 3, 60, 1),
                                         Ray(corner, 120, 3, 60, 2)};
  EXPECT_TRUE(FindYCandidates(segments, 200, 160, 4).empty());
}

// Three lines that do not meet near one point are no Y.
TEST(YJunctionsTest, RaysThatDoNotMeetAreNoY) {
  const std::vector<Segment> segments = {
      Ray({100, 80}, 90, 3, 60, 0), Ray({140, 80}, 210, 3, 70, 1), Ray({100, 40}, 330, 3, 65, 2)};
  EXPECT_TRUE(FindYCandidates(segments, 200, 160, 4).empty());
}

}  // namespace
}  // namespace monocle::corner_detection
