// The floor map: its pixels are where it says on the floor, its colours are floor measure's
// 1 sigma there, it grows with distance as Xu et al.'s section 4 says, and it is empty where
// the camera does not see the floor.
#include "client/cli/floor_map.h"

#include <gtest/gtest.h>

#include <cmath>

#include "service/geometry/test_scenes.h"
#include "service/pipeline/point_queries.h"

namespace monocle::cli {
namespace {

CameraCalibration PaperFloorCamera() {
  CameraCalibration cal;
  cal.intrinsics = testing::PaperCamera();
  cal.floor = FloorCalibration{};
  cal.floor->pose = FloorPose{1.05, 2.0595, 0.0698, 0.0262};
  cal.floor->covariance = FloorCovariance::Identity() * 1e-6;
  return cal;
}

double SigmaAt(const FloorMap& map, double x_m, double y_m) {
  const int col = static_cast<int>(std::floor(map.origin_px.x + x_m / map.metres_per_px));
  const int row = static_cast<int>(std::floor(map.origin_px.y - y_m / map.metres_per_px));
  return map.sigma_m.at<double>(row, col);
}

TEST(FloorMap, EachCellShowsFloorMeasuresSigmaForThePixelThatSeesIt) {
  const CameraCalibration cal = PaperFloorCamera();
  FloorMapOptions o;
  auto map = RenderFloorMap(cal, o);
  ASSERT_TRUE(map.ok()) << map.error();
  EXPECT_EQ(map->picture.cols, static_cast<int>(std::lround(2 * o.range_m / o.metres_per_px)));
  // Cell centres (grid pitch 2 cm from x = -6 m, y = 6 m): x = 0.01 + 0.02 i, y = 0.01 + 0.02 j.
  int checked = 0;
  for (const auto& [x, y] : {std::pair{0.01, 2.01}, {0.41, 1.51}, {-0.39, 3.01}, {0.81, 4.51}}) {
    const double shown = SigmaAt(*map, x, y);
    const auto px = ProjectRobotPoint(cal.intrinsics, cal.floor->pose, Eigen::Vector3d(x, y, 0));
    ASSERT_TRUE(px.has_value());
    const RequestAnswer a = AnswerPointRequest(
        {{"c", cal}}, "c", {PixelQuery{px->x(), px->y(), std::nullopt}}, o.pixel_sigma_px);
    ASSERT_EQ(a.points.size(), 1u);
    if (a.points[0].status != PointStatus::kMeasured) continue;
    // The pixel sees the floor point the map put there (a round trip through the model).
    EXPECT_NEAR(a.points[0].p_robot_m[0], x, 1e-6);
    EXPECT_NEAR(a.points[0].p_robot_m[1], y, 1e-6);
    const auto& s = a.points[0].sigma_m;
    EXPECT_NEAR(shown, std::hypot(s[0], s[1]), 1e-12) << x << "," << y;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

TEST(FloorMap, SigmaGrowsWithDistanceAndIsEmptyWhereTheFloorIsNotSeen) {
  auto map = RenderFloorMap(PaperFloorCamera(), FloorMapOptions{});
  ASSERT_TRUE(map.ok()) << map.error();
  double previous = 0;
  int seen = 0;
  for (double y = 1.5; y <= 5.0; y += 0.5) {
    const double s = SigmaAt(*map, 0.01, y + 0.01);
    if (!std::isfinite(s)) continue;
    EXPECT_GT(s, previous) << "at " << y << " m";
    previous = s;
    ++seen;
  }
  EXPECT_GE(seen, 5);
  EXPECT_TRUE(std::isnan(SigmaAt(*map, 0.01, -0.3))) << "behind the robot";
  EXPECT_TRUE(std::isnan(SigmaAt(*map, -5.5, 1.0))) << "far outside the field of view";
}

TEST(FloorMap, AnUncalibratedFloorSaysWhatToDo) {
  CameraCalibration cal = PaperFloorCamera();
  cal.floor.reset();
  auto map = RenderFloorMap(cal, FloorMapOptions{});
  ASSERT_FALSE(map.ok());
  EXPECT_NE(map.error().message.find("floor calibrate"), std::string::npos);
  FloorMapOptions tiny;
  tiny.metres_per_px = 0.0001;
  EXPECT_FALSE(RenderFloorMap(PaperFloorCamera(), tiny).ok());
}

}  // namespace
}  // namespace monocle::cli
