// Point queries over DDS: monocled in its own process answers like the offline tool on the
// same calibration file, and every malformed request gets a typed error while it keeps
// serving.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "client/point_client.h"
#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 26;

std::string Monocled() {
  const std::string bin = testing::MonocleBinary();
  return bin.substr(0, bin.rfind("/client/")) + "/service/monocled";
}

class PointQueryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv(
        "CYCLONEDDS_URI",
        ("file://" + std::string(MONOCLE_SOURCE_DIR) + "/docker/cyclonedds-loopback.xml").c_str(),
        1);
    CameraCalibration cal;
    cal.intrinsics = testing::PaperCamera();
    cal.floor = FloorCalibration{};
    cal.floor->pose = FloorPose{1.05, 2.0595, 0.0698, 0.0262};
    cal.floor->covariance = FloorCovariance::Identity() * 1e-8;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "floor.pbtxt", cal).ok());
    monocled_ = std::make_unique<testing::ChildProcess>(
        Monocled(),
        std::vector<std::string>{"--floor-camera", "floor", "--floor-calibration",
                                 dir_ / "floor.pbtxt", "--domain", std::to_string(kDomain)},
        dir_ / "monocled.log");
  }
  void TearDown() override {
    EXPECT_EQ(monocled_->Stop(), 0) << testing::ReadFile(dir_ / "monocled.log");
  }

  TempDir dir_{"monocle_point_query"};
  std::unique_ptr<testing::ChildProcess> monocled_;
};

TEST_F(PointQueryTest, AnswersEqualTheOfflineToolOnTheSameFile) {
  const std::string points = "640,900 100,1000 1200,700 482,544@484,674 640,2 5000,1";
  const auto live = RunMonocle(dir_, "floor measure --camera floor --json --timeout 30 --domain " +
                                         std::to_string(kDomain) + " " + points);
  const auto offline =
      RunMonocle(dir_, "floor measure --json --calibration " + dir_ / "floor.pbtxt" + " " + points);
  EXPECT_EQ(live.exit_code, offline.exit_code) << live.err;
  google::protobuf::ListValue a, b;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(live.out, &a).ok())
      << live.out << live.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(offline.out, &b).ok()) << offline.out;
  ASSERT_EQ(a.values_size(), 6);
  ASSERT_EQ(b.values_size(), 6);
  for (int i = 0; i < 6; ++i) {
    const auto& pa = a.values(i).struct_value().fields();
    const auto& pb = b.values(i).struct_value().fields();
    ASSERT_EQ(pa.count("error"), pb.count("error")) << i;
    if (pa.count("error")) {
      EXPECT_EQ(pa.at("error").string_value(), pb.at("error").string_value());
      continue;
    }
    for (const char* k : {"x", "y", "z"})
      EXPECT_EQ(pa.at(k).number_value(), pb.at(k).number_value()) << k;
    for (const char* k : {"x", "y", "z"}) {
      const double sa = pa.at("sigma").struct_value().fields().at(k).number_value();
      const double sb = pb.at("sigma").struct_value().fields().at(k).number_value();
      EXPECT_NEAR(sa, sb, 1e-12 * std::max(1.0, sb)) << "sigma " << k;
    }
  }
}

TEST_F(PointQueryTest, MalformedRequestsGetTypedErrorsAndTheServiceKeepsServing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto ask = [&](const std::string& camera, const std::vector<PixelPair>& points) {
    return client::MeasurePoints(camera, points, 0.5, kDomain, 30);
  };
  auto r = ask("floor", {{nan, 800}, {640, 5000}, {640, 800, true, nan, 1}});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->status, RequestStatus::kAnswered);
  for (const auto& p : r->points) EXPECT_EQ(p.status, PointStatus::kInvalidPixel) << p.error;

  r = ask("floor", {});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->status, RequestStatus::kInvalidRequest);
  EXPECT_NE(r->error.find("no points"), std::string::npos);

  r = ask("floor", std::vector<PixelPair>(1000000, PixelPair{640, 800}));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->status, RequestStatus::kInvalidRequest);
  EXPECT_NE(r->error.find("too many points"), std::string::npos);

  r = ask("no-such-camera", {{640, 800}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->status, RequestStatus::kInvalidRequest);
  EXPECT_NE(r->error.find("unknown floor camera 'no-such-camera'"), std::string::npos);

  // Still serving.
  r = ask("floor", {{640, 800}});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->points.size(), 1u);
  EXPECT_EQ(r->points[0].status, PointStatus::kMeasured);
  EXPECT_GT(r->points[0].measurement.p_robot_m.y(), 0);
}

}  // namespace
}  // namespace monocle
