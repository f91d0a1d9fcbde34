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
  const auto a = AnswerPointRequest(cams, "floor", {{640, 900, {}}, {640, 500, {{640, 900}}}}, 0.5);
  ASSERT_EQ(a.status, RequestStatus::kAnswered);
  ASSERT_EQ(a.points.size(), 2u);
  const auto direct = MeasureFloorPoint(cams.at("floor").intrinsics, cams.at("floor").floor->pose,
                                        {FloorCovariance::Zero(), 0.5}, {640, 900});
  EXPECT_EQ(a.points[0].p_robot_m[0], direct->p_robot_m.x());
  EXPECT_EQ(a.points[0].p_robot_m[1], direct->p_robot_m.y());
  EXPECT_EQ(a.points[1].status, PointStatus::kMeasured);
  EXPECT_GT(a.points[1].p_robot_m[2], 0);
}

TEST(PointQueriesTest, KeepsTheFullCovarianceRowMajor) {
  const auto cams = Cameras();
  const auto& floor = *cams.at("floor").floor;
  const auto direct = MeasureFloorPoint(cams.at("floor").intrinsics, floor.pose,
                                        {FloorCovariance::Zero(), 0.5}, {900, 700});
  ASSERT_TRUE(direct);
  const auto a = AnswerPointRequest(cams, "floor", {{900, 700, {}}}, 0.5);
  ASSERT_EQ(a.points.size(), 1u);
  const MeasuredPoint& p = a.points[0];
  // A point off the axis has correlated x and y: the off-diagonal must survive, in its place.
  ASSERT_NE(direct->covariance(0, 1), 0);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(p.covariance[3 * r + c], direct->covariance(r, c),
                  1e-12 * direct->covariance.norm());
      EXPECT_EQ(p.covariance[3 * r + c], p.covariance[3 * c + r]) << "symmetric to the bit";
    }
    EXPECT_DOUBLE_EQ(p.sigma_m[r], std::sqrt(direct->covariance(r, r)));
  }
}

TEST(PointQueriesTest, EveryMalformedInputIsATypedError) {
  const auto cams = Cameras();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(AnswerPointRequest(cams, "nope", {{1, 1, {}}}, 0.5).status,
            RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "bare", {{1, 1, {}}}, 0.5).status,
            RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", {}, 0.5).status, RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", std::vector<PixelQuery>(1000000), 0.5).status,
            RequestStatus::kInvalidRequest);
  EXPECT_EQ(AnswerPointRequest(cams, "floor", {{1, 1, {}}}, nan).status,
            RequestStatus::kInvalidRequest);
  const auto a = AnswerPointRequest(
      cams, "floor", {{nan, 1, {}}, {5000, 1, {}}, {640, 2, {}}, {640, 900, {{nan, 1}}}}, 0.5);
  ASSERT_EQ(a.status, RequestStatus::kAnswered);
  EXPECT_EQ(a.points[0].status, PointStatus::kInvalidPixel);
  EXPECT_EQ(a.points[1].status, PointStatus::kInvalidPixel);
  EXPECT_EQ(a.points[2].status, PointStatus::kMeasured);  // this camera sees floor at the top row
  EXPECT_EQ(a.points[3].status, PointStatus::kInvalidPixel);
}

}  // namespace
}  // namespace monocle
