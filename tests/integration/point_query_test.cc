// Point queries over DDS: monocled in its own process answers like the offline tool on the
// same calibration file, and every malformed request gets a typed error while it keeps
// serving.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "monocle/client.h"
#include "tests/integration/paper_floor_calibration.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 26;

class PointQueryTest : public testing::ServiceTest {
 protected:
  PointQueryTest() : ServiceTest("monocle_point_query") {}
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(testing::WritePaperFloorCalibration(dir_ / "floor.pbtxt"));
    // The point queries use only the calibration file; the camera gives the status.
    ASSERT_NO_FATAL_FAILURE(StartService(kDomain, R"(
camera { id: "floor" device: "sim-floor" role: FLOOR calibration: "floor.pbtxt" }
camera { id: "corner" device: "sim-corner" role: CORNER calibration: "floor.pbtxt"
         ceiling_distance_m: 1.6 }
)"));
  }
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
  auto r = client_->measure("floor", {{nan, 800, std::nullopt},
                                      {640, 5000, std::nullopt},
                                      {640, 800, std::array<double, 2>{nan, 1}}});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->size(), 3u);
  for (const auto& p : *r) EXPECT_EQ(p.status, MeasuredPoint::Status::kInvalidPixel) << p.error;

  r = client_->measure("floor", {});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_NE(r.error().message.find("no points"), std::string::npos) << r.error();

  r = client_->measure("floor", std::vector<PixelQuery>(1000000, PixelQuery{640, 800, {}}));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_NE(r.error().message.find("too many points"), std::string::npos) << r.error();

  r = client_->measure("no-such-camera", {{640, 800, {}}});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_NE(r.error().message.find("unknown camera 'no-such-camera'"), std::string::npos);

  // Issue 14: a 1 MB camera id was echoed back whole in the error.
  r = client_->measure(std::string(1 << 20, 'x'), {{640, 800, {}}});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_LT(r.error().message.size(), 400u);
  EXPECT_NE(r.error().message.find("(1048576 characters)"), std::string::npos) << r.error();

  // Issue 14: sim-corner was called an "unknown floor camera"; it is a corner camera.
  r = client_->measure("corner", {{640, 800, {}}});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_NE(r.error().message.find("camera 'corner' is not a floor camera (role corner)"),
            std::string::npos)
      << r.error();

  // Issue 14: a paired point whose top is below its foot got a negative height silently.
  r = client_->measure("floor", {{640, 900, std::array<double, 2>{640, 700}}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ((*r)[0].status, MeasuredPoint::Status::kNotMeasurable);
  EXPECT_NE((*r)[0].error.find("is below its foot"), std::string::npos) << (*r)[0].error;

  // Still serving.
  r = client_->measure("floor", {{640, 800, {}}});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->size(), 1u);
  EXPECT_TRUE((*r)[0].ok()) << (*r)[0].error;
  EXPECT_GT((*r)[0].p_robot_m[1], 0);
}

TEST(PointQueryNoServiceTest, NoServiceIsAClearError) {
  testing::UseLoopbackDds();
  // A domain no other test uses (tracking_stream_test serves 27 while this may run).
  auto client = Client::open({59, std::chrono::milliseconds(500)});
  ASSERT_TRUE(client.ok()) << client.error();
  const auto r = client->measure("floor", {{640, 800, {}}});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ClientError::Code::kNoService);
  EXPECT_NE(r.error().message.find("is monocled running"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace monocle
