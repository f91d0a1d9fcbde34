#include "service/pipeline/point_queries.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

std::map<std::string, CameraCalibration> Cameras() {
  CameraCalibration cal;
  cal.intrinsics = testing::PaperCamera();
  cal.floor = FloorCalibration{};
  cal.floor->pose = FloorPose{1.05, 2.0595, 0.0698, 0.0262};
  CameraCalibration uncalibrated;
  uncalibrated.intrinsics = cal.intrinsics;
  return {{"floor", cal}, {"bare", uncalibrated}};
}

TEST(PointQueriesTest, MeasuresLikeTheFloorModel) {
  const auto cams = Cameras();
  const auto a = AnswerPointRequest(cams, "floor", {{640, 900}, {640, 500, true, 640, 900}}, 0.5);
  ASSERT_EQ(a.status, RequestStatus::kAnswered);
  ASSERT_EQ(a.points.size(), 2u);
  const auto direct = MeasureFloorPoint(cams.at("floor").intrinsics, cams.at("floor").floor->pose,
                                        {FloorCovariance::Zero(), 0.5}, {640, 900});
  EXPECT_EQ(a.points[0].measurement.p_robot_m, direct->p_robot_m);
  EXPECT_EQ(a.points[1].status, PointStatus::kMeasured);
  EXPECT_GT(a.points[1].measurement.p_robot_m.z(), 0);
}

TEST(PointQueriesTest, EveryMalformedInputIsATypedError) {
  const auto cams = Cameras();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(AnswerPointRequest(cams, "nope", {{1, 1}}, 0.5).status, RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "bare", {{1, 1}}, 0.5).status, RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", {}, 0.5).status, RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", std::vector<PixelPair>(1000000), 0.5).status,
            RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", {{1, 1}}, nan).status,
            RequestStatus::kInvalidRequest);
  const auto a = AnswerPointRequest(cams, "floor",
                                    {{nan, 1}, {5000, 1}, {640, 2}, {640, 900, true, nan, 1}}, 0.5);
  ASSERT_EQ(a.status, RequestStatus::kAnswered);
  EXPECT_EQ(a.points[0].status, PointStatus::kInvalidPixel);
  EXPECT_EQ(a.points[1].status, PointStatus::kInvalidPixel);
  EXPECT_EQ(a.points[2].status, PointStatus::kMeasured);  // this camera sees floor at the top row
  EXPECT_EQ(a.points[3].status, PointStatus::kInvalidPixel);
}

}  // namespace
}  // namespace monocle
