// One corner pipeline: monocled with a mount and a room map records every frame it processes
// (`--record --record-frames every`), and `monocle replay` of that recording, given the same
// map, mount and initial pose, gives the map poses monocled published, bit for bit. The
// frames come from the simulated GigE Vision camera (`monocle simcam --scene room`) driving
// the example hall slowly enough that monocled processes every frame.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "idl/cli_output.pb.h"
#include "idl/monocle_msgs.h"
#include "idl/protocol/cdr.h"
#include "idl/protocol/convert.h"
#include "monocle/client.h"
#include "service/io/mcap_reader.h"
#include "tests/integration/room_drive.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

constexpr int kDomain = 83;
const std::string kExamples = testing::kRoomExamples;
// Frames to record: enough for the map tracker to carry its prior through many frames and
// for the corner tracker to detect again (every 30 frames).
constexpr size_t kFrames = 40;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

class ReplayMapTest : public testing::ServiceTest {
 protected:
  ReplayMapTest() : ServiceTest("monocle_replay_map") {}
};

TEST_F(ReplayMapTest, ReplayInTheRoomMapGivesTheMapPosesMonocledPublished) {
  // 4 frames a second: monocled (about 5 ms a frame) processes every one, so live and replay
  // see the same sequence. Under ThreadSanitizer, 1 a second.
  const std::string fps = testing::kThreadSanitizer ? "1" : "4";
  std::unique_ptr<testing::ChildProcess> simcam;
  ASSERT_NO_FATAL_FAILURE(testing::StartRoomDrive(dir_, "7", fps, &simcam));
  const std::string recording = dir_ / "map.mcap";
  // The configuration's mount is idl/examples/camera_mount.pbtxt's, the initial pose the
  // drive's start (RoomDriveCameraConfig): what the replay is given again below.
  ASSERT_NO_FATAL_FAILURE(StartService(kDomain, testing::RoomDriveCameraConfig(),
                                       {"--record", recording, "--record-frames", "every"}));
  std::atomic<size_t> poses{0};
  auto sub = client_->subscribe_poses([&](const Pose&) { ++poses; }, "front");
  ASSERT_TRUE(sub.ok()) << sub.error();
  for (int i = 0; i < 1200 && poses < kFrames; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  sub->stop();
  auto status = client_->status();
  ASSERT_TRUE(status.ok()) << status.error();
  for (const auto& c : *status) {
    if (c.camera_id == "front") {
      EXPECT_EQ(c.skipped, 0u) << "monocled skipped frames";
    }
  }
  ASSERT_EQ(monocled_->Stop(), 0) << testing::ReadFile(dir_ / "monocled.log");
  monocled_.reset();
  EXPECT_EQ(simcam->Stop(), 0);
  ASSERT_GE(poses.load(), kFrames) << testing::ReadFile(dir_ / "monocled.log");

  // The recording: every frame, and the pose monocled published for each.
  auto reader = mcap::Reader::Open(recording);
  ASSERT_TRUE(reader.ok()) << reader.error();
  std::set<int64_t> frames;
  std::map<int64_t, Pose> published;
  ASSERT_TRUE(reader
                  ->ForEachMessage([&](const mcap::ChannelInfo& ch, const mcap::Message& m) {
                    if (ch.topic == "/monocle/front/image_raw") {
                      auto s = dds::DecodedSample<sensor_msgs_msg_dds__Image_>::Decode(
                          &sensor_msgs_msg_dds__Image__desc, m.data);
                      if (s) {
                        frames.insert(int64_t{s->get().header.stamp.sec} * 1000000000 +
                                      s->get().header.stamp.nanosec);
                      }
                    } else if (ch.topic == "/monocle/front/corner_pose") {
                      auto s = dds::DecodedSample<monocle_msgs_msg_dds__CornerPose_>::Decode(
                          &monocle_msgs_msg_dds__CornerPose__desc, m.data);
                      if (s) {
                        const Pose p = wire::FromSample(s->get());
                        published[p.capture_time_ns] = p;
                      }
                    }
                    return true;
                  })
                  .ok());
  ASSERT_GE(published.size(), kFrames);
  // Live processed exactly the recorded frames, from the first on: the recorder starts before
  // the camera, and nothing was skipped.
  std::set<int64_t> pose_stamps;
  for (const auto& [stamp, pose] : published) pose_stamps.insert(stamp);
  ASSERT_EQ(pose_stamps, frames) << "a frame processed live is missing from the recording, or "
                                    "a recorded frame was not processed";

  const auto replay = testing::RunMonocle(
      dir_, "replay --json " + recording + " --map " + kExamples + "room_map.pbtxt --mount " +
                kExamples + "camera_mount.pbtxt --prior 1.4,1.3,-20");
  std::map<int64_t, proto::LivePoseOutput> replayed;
  std::istringstream lines(replay.out);
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok()) << line;
    replayed[out.capture_time_ns()] = out;
  }
  ASSERT_EQ(replayed.size(), frames.size()) << replay.err;
  int located = 0;
  for (const auto& [stamp, live] : published) {
    const auto& again = replayed.at(stamp).pose();
    const std::string what = "frame at " + std::to_string(stamp);
    ASSERT_EQ(live.valid, !again.has_error()) << what;
    if (!live.valid) continue;
    EXPECT_TRUE(SameBits(live.x_m, again.x()) && SameBits(live.y_m, again.y())) << what;
    ASSERT_TRUE(again.has_map()) << what;
    EXPECT_EQ(ToString(live.map_status), again.map().status()) << what;
    if (live.map_status != MapStatus::kLocated) continue;
    ++located;
    const auto& m = again.map().pose();
    EXPECT_EQ(live.map_corner, m.corner()) << what;
    EXPECT_TRUE(SameBits(live.map_x_m, m.x())) << what << ": " << live.map_x_m << " vs " << m.x();
    EXPECT_TRUE(SameBits(live.map_y_m, m.y())) << what << ": " << live.map_y_m << " vs " << m.y();
    EXPECT_TRUE(SameBits(std::sqrt(live.map_covariance[0]), m.sigma().x())) << what;
    EXPECT_TRUE(SameBits(std::sqrt(live.map_covariance[4]), m.sigma().y())) << what;
    EXPECT_NEAR(live.map_heading_rad * 180 / M_PI, m.heading_deg(), 1e-12) << what;
  }
  std::cout << published.size() << " frames recorded and processed, " << located
            << " located in the map, replayed bit for bit\n";
  EXPECT_GE(located, static_cast<int>(kFrames) / 2);
}

}  // namespace
}  // namespace monocle
