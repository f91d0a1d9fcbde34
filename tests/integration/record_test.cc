// `monocle record` against a real monocled on the simulated cameras, each in its own process
// on loopback: what the recording holds equals what a client received (every pose bit for
// bit, point replies too), an independent reader of the file agrees with monocle's, and a
// recorder killed with SIGKILL leaves a file `monocle info` recovers.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <mutex>
#include <thread>

#include "idl/monocle_msgs.h"
#include "idl/protocol/cdr.h"
#include "idl/protocol/convert.h"
#include "monocle/client.h"
#include "service/io/mcap_reader.h"
#include "tests/integration/paper_floor_calibration.h"
#include "tests/integration/service_process.h"
#include "tests/mcap_spec_reader.h"

namespace monocle {
namespace {

using testing::ChildProcess;
using testing::RunMonocle;

constexpr int kDomain = 61;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every field of two poses, doubles compared bit for bit.
void ExpectIdentical(const Pose& a, const Pose& b) {
  EXPECT_EQ(a.camera_id, b.camera_id);
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.frame_sequence, b.frame_sequence);
  EXPECT_EQ(a.capture_time_ns, b.capture_time_ns);
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.error, b.error);
  for (auto [x, y] : {std::pair{a.x_m, b.x_m},
                      {a.y_m, b.y_m},
                      {a.z_m, b.z_m},
                      {a.pan_rad, b.pan_rad},
                      {a.tilt_rad, b.tilt_rad},
                      {a.swing_rad, b.swing_rad},
                      {a.rms_px, b.rms_px}}) {
    EXPECT_TRUE(SameBits(x, y)) << x << " vs " << y;
  }
  EXPECT_EQ(std::memcmp(a.quaternion_wxyz.data(), b.quaternion_wxyz.data(), 32), 0);
  EXPECT_EQ(std::memcmp(a.covariance.data(), b.covariance.data(), 25 * 8), 0);
  EXPECT_EQ(std::memcmp(a.corner_px.data(), b.corner_px.data(), 16), 0);
  EXPECT_EQ(a.processing_ns, b.processing_ns);
  EXPECT_EQ(a.tracked, b.tracked);
  EXPECT_EQ(a.suspect, b.suspect);
}

class RecordTest : public testing::ServiceTest {
 protected:
  RecordTest() : ServiceTest("monocle_record") {}
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(testing::WritePaperFloorCalibration(dir_ / "floor.pbtxt"));
    ASSERT_NO_FATAL_FAILURE(StartService(kDomain, R"(
camera { id: "floor" device: "sim-floor" role: FLOOR calibration: "floor.pbtxt" }
camera { id: "corner" device: "sim-corner" role: CORNER calibration: "floor.pbtxt"
         ceiling_distance_m: 1.6 }
)"));
    // Until both cameras stream (their topics exist), so the recorder finds them.
    for (int i = 0; i < 600; ++i) {
      auto s = client_->status();
      int streaming = 0;
      if (s) {
        for (const auto& c : *s) streaming += c.state == CameraState::kStreaming;
      }
      if (streaming == 2) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    FAIL() << "the simulated cameras did not stream";
  }

  std::unique_ptr<ChildProcess> StartRecorder(const std::string& file,
                                              const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{
        "record", "--domain", std::to_string(kDomain), "--out", dir_ / file, "--timeout", "30"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto p = std::make_unique<ChildProcess>(testing::MonocleBinary(), args, dir_ / "record.log");
    // The recorder has subscribed once its file exists and a moment has passed for discovery.
    for (int i = 0; i < 600 && !std::filesystem::exists(dir_ / file); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    return p;
  }
};

TEST_F(RecordTest, TheRecordingHoldsExactlyWhatTheClientReceived) {
  auto recorder = StartRecorder("session.mcap", {"--zstd", "--frames", "2"});

  std::mutex mutex;
  std::map<uint64_t, Pose> received;  // by frame sequence
  auto sub = client_->subscribe_poses([&](const Pose& p) {
    std::lock_guard lock(mutex);
    received[p.frame_sequence] = p;
  });
  ASSERT_TRUE(sub.ok()) << sub.error();
  std::vector<std::vector<MeasuredPoint>> answers;
  // At least 5 requests, and until more than 5 poses arrived (a slow build, e.g. under
  // ThreadSanitizer, publishes a pose or two a second).
  auto enough_poses = [&] {
    std::lock_guard lock(mutex);
    return received.size() > 5;
  };
  for (int i = 0; i < 120 && (i < 5 || !enough_poses()); ++i) {
    auto points = client_->measure(
        "floor", {PixelQuery{640.0 + i, 900.0, std::nullopt}, PixelQuery{100, 1000, std::nullopt}});
    ASSERT_TRUE(points.ok()) << points.error();
    answers.push_back(*points);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  sub->stop();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(recorder->Stop(), 0) << testing::ReadFile(dir_ / "record.log");

  auto reader = mcap::Reader::Open(dir_ / "session.mcap");
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_TRUE(reader->summary().from_index);
  EXPECT_EQ(reader->chunks_read(), 0u) << "the summary must come from the index";
  std::map<uint64_t, Pose> recorded;
  // By request number: the client sends a request again when its reply is late (50 ms), and
  // each copy is answered; the answers to one request are the same.
  std::map<int64_t, std::vector<MeasuredPoint>> replies;
  int images = 0, calibrations = 0;
  ASSERT_TRUE(reader
                  ->ForEachMessage([&](const mcap::ChannelInfo& ch, const mcap::Message& m) {
                    if (ch.topic == "/monocle/corner/corner_pose") {
                      auto s = dds::DecodedSample<monocle_msgs_msg_dds__CornerPose_>::Decode(
                          &monocle_msgs_msg_dds__CornerPose__desc, m.data);
                      EXPECT_NE(s, nullptr) << "undecodable pose";
                      if (s) recorded[s->get().frame_sequence] = wire::FromSample(s->get());
                    } else if (ch.topic == "/monocle/floor/measure_points/reply") {
                      auto s =
                          dds::DecodedSample<monocle_msgs_srv_dds__MeasurePoints_Response_>::Decode(
                              &monocle_msgs_srv_dds__MeasurePoints_Response__desc, m.data);
                      EXPECT_NE(s, nullptr);
                      if (s) replies[s->get().seq] = *wire::FromSample(s->get());
                    } else if (ch.topic.ends_with("/image_raw")) {
                      ++images;
                    } else if (ch.topic == "/monocle/calibrations") {
                      ++calibrations;
                    }
                    return true;
                  })
                  .ok());

  // Every pose the client received is in the recording, equal bit for bit.
  ASSERT_GT(received.size(), 5u);
  for (const auto& [seq, pose] : received) {
    const auto it = recorded.find(seq);
    ASSERT_NE(it, recorded.end()) << "frame " << seq << " was received but not recorded";
    ExpectIdentical(it->second, pose);
  }
  // Every point answer too (the recorder saw the replies to this client).
  ASSERT_EQ(replies.size(), answers.size());
  size_t i = 0;
  for (const auto& [seq, reply] : replies) {
    ASSERT_EQ(reply.size(), answers[i].size()) << "request " << seq;
    for (size_t j = 0; j < reply.size(); ++j) {
      EXPECT_EQ(std::memcmp(reply[j].p_robot_m.data(), answers[i][j].p_robot_m.data(), 24), 0);
      EXPECT_EQ(std::memcmp(reply[j].sigma_m.data(), answers[i][j].sigma_m.data(), 24), 0);
    }
    ++i;
  }
  EXPECT_GT(images, 0) << "--frames 2 records every second frame the service sends";
  EXPECT_GE(calibrations, 2) << "both cameras' calibrations (transient-local)";

  // An independent reader lists the same channels and counts.
  const testing::SpecReadResult spec = testing::SpecRead(dir_ / "session.mcap");
  const mcap::Summary& s = reader->summary();
  EXPECT_EQ(spec.messages, s.message_count);
  EXPECT_EQ(spec.statistics_message_count, s.message_count);
  for (const auto& [id, ch] : s.channels) {
    EXPECT_EQ(spec.topics.at(id), ch.topic);
    const auto n = s.channel_message_counts.count(id) ? s.channel_message_counts.at(id) : 0;
    EXPECT_EQ(spec.counts.count(ch.topic) ? spec.counts.at(ch.topic) : 0, n) << ch.topic;
    EXPECT_EQ(spec.schema_names.at(spec.channel_schema.at(id)), s.schemas.at(ch.schema_id).name);
  }

  // monocle info says the same, from the index.
  const auto info = RunMonocle(dir_, "info --json " + dir_ / "session.mcap");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("\"messages\":" + std::to_string(s.message_count)), std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("\"from_index\":true"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("\"/monocle/corner\""), std::string::npos) << info.out;
}

// --frames every gets what the service sends, at most its image_max_rate_hz: the recorder says
// so before it starts, how to get every frame, and afterwards how many of each camera's frames
// it got.
TEST_F(RecordTest, FramesEverySaysWhatItGetsAndHowToGetMore) {
  auto recorder = StartRecorder("frames.mcap", {"--frames", "every", "--duration", "3"});
  std::this_thread::sleep_for(std::chrono::seconds(3));
  ASSERT_EQ(recorder->Stop(), 0) << testing::ReadFile(dir_ / "record.log");
  const std::string log = testing::ReadFile(dir_ / "record.log");
  EXPECT_NE(log.find("at most at its image_max_rate_hz"), std::string::npos) << log;
  EXPECT_NE(log.find("monocled --record FILE.mcap --record-frames every"), std::string::npos)
      << log;
  // The simulated corner camera runs at 30 fps, the service sends 5 a second.
  EXPECT_NE(log.find("monocle: corner: "), std::string::npos) << log;
  EXPECT_NE(log.find("image_max_rate_hz caps them"), std::string::npos) << log;
}

TEST_F(RecordTest, ARecorderKilledWithSigkillLeavesARecoverableFile) {
  auto recorder = StartRecorder("killed.mcap", {"--frames", "every"});
  std::this_thread::sleep_for(std::chrono::seconds(4));
  kill(recorder->pid(), SIGKILL);
  EXPECT_EQ(recorder->Stop(), -1);
  const auto info = RunMonocle(dir_, "info " + dir_ / "killed.mcap");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("recovered:"), std::string::npos) << info.out;
  auto reader = mcap::Reader::Open(dir_ / "killed.mcap");
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_TRUE(reader->summary().recovered);
  EXPECT_GT(reader->summary().message_count, 0u) << "complete chunks were on disk";
  EXPECT_EQ(testing::SpecRead(dir_ / "killed.mcap").messages, reader->summary().message_count);
}

TEST_F(RecordTest, AFileSizeLimitEndsTheRecordingWithAnIndexedFileAndAnError) {
  // As a full disk would: the recorder's writes fail beyond 3 MB (prlimit, util-linux).
  std::vector<std::string> args{"--fsize=3000000",
                                testing::MonocleBinary(),
                                "record",
                                "--domain",
                                std::to_string(kDomain),
                                "--out",
                                dir_ / "full.mcap",
                                "--frames",
                                "every",
                                "--duration",
                                "60",
                                "--timeout",
                                "30"};
  ChildProcess limited("/usr/bin/prlimit", args, dir_ / "full.log");
  const std::optional<int> status = limited.WaitFor(std::chrono::seconds(60));
  const std::string log = testing::ReadFile(dir_ / "full.log");
  ASSERT_EQ(status, std::optional<int>(1))
      << "the recording must stop by itself with exit status 1: " << log;
  EXPECT_NE(log.find("size limit"), std::string::npos) << log;
  auto reader = mcap::Reader::Open(dir_ / "full.mcap");
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_TRUE(reader->summary().from_index) << "the summary was written after the failure";
  EXPECT_GT(reader->summary().message_count, 0u);
}

}  // namespace
}  // namespace monocle
