#include "service/io/calibration_file.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace monocle {
namespace {

constexpr const char* kIssueExample =
    R"(intrinsics { width: 1280 height: 1024 fx: 1624.34 fy: 1623.04 cx: 634.77 cy: 499.02
             distortion: [-0.07021, 0.07348, -0.00112, 0.00267] }
floor { height: 1.013 pitch: 1.8354 yaw: -0.0119 roll: 0 }
)";

TEST(CalibrationFileTest, ParsesTheDocumentedExample) {
  const auto cal = ParseCalibration(kIssueExample, "example.pbtxt");
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_EQ(cal->intrinsics.width_px, 1280);
  EXPECT_DOUBLE_EQ(cal->intrinsics.fy, 1623.04);
  EXPECT_DOUBLE_EQ(cal->intrinsics.distortion[3], 0.00267);
  EXPECT_DOUBLE_EQ(cal->intrinsics.distortion[4], 0.0);
  ASSERT_TRUE(cal->floor.has_value());
  EXPECT_DOUBLE_EQ(cal->floor->pose.height_m, 1.013);
  EXPECT_DOUBLE_EQ(cal->floor->pose.pitch_rad, 1.8354);
  EXPECT_DOUBLE_EQ(cal->floor->pose.yaw_rad, -0.0119);
  EXPECT_FALSE(cal->ceiling_distance_m.has_value());
}

TEST(CalibrationFileTest, FloorSectionIsOptional) {
  const auto cal = ParseCalibration(
      "intrinsics { width: 640 height: 480 fx: 500 fy: 500 cx: 320 cy: 240 }", "f");
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_FALSE(cal->floor.has_value());
}

struct BadCase {
  const char* text;
  const char* expected_in_message;
};

class BrokenCalibrationTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(BrokenCalibrationTest, IsRejectedNamingTheProblem) {
  const auto cal = ParseCalibration(GetParam().text, "cal.pbtxt");
  ASSERT_FALSE(cal.ok());
  EXPECT_NE(cal.error().message.find(GetParam().expected_in_message), std::string::npos)
      << cal.error();
  EXPECT_NE(cal.error().message.find("cal.pbtxt"), std::string::npos) << cal.error();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BrokenCalibrationTest,
    ::testing::Values(
        BadCase{"floor { height: 1 pitch: 1.8 }", "'intrinsics' is missing"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 focal: 3 }",
                "no field named \"focal\""},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\nfloor { height: "
                "1 pitch: 1.8 tilt: 0 }",
                "line 2"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\nfloor { height: "
                "-1 pitch: 1.8 }",
                "'floor.height'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\nfloor { height: "
                "1 pitch: 4 }",
                "'floor.pitch'"},
        BadCase{
            "intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\nfloor { pitch: 1.8 }",
            "'floor.height' is missing"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 0 fy: 1 cx: 1 cy: 1 }",
                "'intrinsics.fx'"},
        BadCase{"intrinsics { width: 0 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }",
                "'intrinsics.width'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 2000 }",
                "'intrinsics.cy'"},
        BadCase{
            "intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 distortion: [1, 2, 3] }",
            "'intrinsics.distortion'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: nan fy: 1 cx: 1 cy: 1 }",
                "'intrinsics.fx'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\ncorner { "
                "ceiling_distance: -2 }",
                "'corner.ceiling_distance'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\ncorner { "
                "max_swing: 0 }",
                "'corner.max_swing'"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\ncorner { "
                "max_swing: 45 }",
                "at most pi"},
        BadCase{"intrinsics { width: 1280 height: 1024 fx: 1 fy: 1 cx: 1 cy: 1 }\nfloor { height: "
                "1 pitch: 1.8 covariance: [1, 2] }",
                "'floor.covariance'"},
        BadCase{"intrinsics { width: 1280", "line 1"}));

TEST(CalibrationFileTest, SaveThenLoadRoundTripsAndLeavesNoTemporaryFile) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("monocle_cal_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "cal.pbtxt").string();
  CameraCalibration cal = *ParseCalibration(kIssueExample, "example");
  cal.floor->covariance = FloorCovariance::Identity() * 1e-6;
  cal.floor->rms_px = 0.07;
  cal.ceiling_distance_m = 1.6;
  cal.corner_max_swing_rad = 1.2;
  ASSERT_TRUE(SaveCalibrationFileAtomically(path, cal).ok());
  const auto back = LoadCalibrationFile(path);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_DOUBLE_EQ(back->intrinsics.cx, cal.intrinsics.cx);
  EXPECT_DOUBLE_EQ(back->floor->pose.pitch_rad, 1.8354);
  EXPECT_DOUBLE_EQ(back->floor->covariance(2, 2), 1e-6);
  EXPECT_DOUBLE_EQ(*back->ceiling_distance_m, 1.6);
  ASSERT_TRUE(back->corner_max_swing_rad.has_value());
  EXPECT_DOUBLE_EQ(*back->corner_max_swing_rad, 1.2);
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

TEST(CalibrationFileTest, MissingFileSaysSo) {
  const auto cal = LoadCalibrationFile("/nonexistent/monocle.pbtxt");
  ASSERT_FALSE(cal.ok());
  EXPECT_NE(cal.error().message.find("/nonexistent/monocle.pbtxt"), std::string::npos);
}

}  // namespace
}  // namespace monocle
