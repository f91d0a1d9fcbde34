// RecordingSource on recordings written here, with sensor_msgs/Image CDR encoded by hand from
// the XCDR1 rules (not by Cyclone DDS, which decodes them): frames in order with their
// stamps and pixels, the end, looping, pacing, and frames that are not what they claim.
#include "camera/recording_source.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "service/io/mcap_writer.h"

namespace monocle {
namespace {

// XCDR1 little-endian: the 4-byte encapsulation header, then each primitive aligned to its
// size counted from the start of the body.
class CdrLe {
 public:
  CdrLe() : out_("\x00\x01\x00\x00", 4) {}
  void U8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void U32(uint32_t v) {
    while ((out_.size() - 4) % 4 != 0) out_.push_back('\0');
    out_.append(reinterpret_cast<const char*>(&v), 4);
  }
  void String(const std::string& s) {
    U32(static_cast<uint32_t>(s.size() + 1));
    out_ += s;
    out_.push_back('\0');
  }
  void Bytes(const std::string& b) {
    U32(static_cast<uint32_t>(b.size()));
    out_ += b;
  }
  const std::string& str() const { return out_; }

 private:
  std::string out_;
};

std::string ImageCdr(int64_t stamp_ns, uint32_t width, uint32_t height, const std::string& encoding,
                     const std::string& pixels, uint32_t step = 0) {
  CdrLe c;
  c.U32(static_cast<uint32_t>(stamp_ns / 1000000000));
  c.U32(static_cast<uint32_t>(stamp_ns % 1000000000));
  c.String("cam_optical");
  c.U32(height);
  c.U32(width);
  c.String(encoding);
  c.U8(0);
  c.U32(step == 0 ? width : step);
  c.Bytes(pixels);
  return c.str();
}

class RecordingSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("monocle_recording_source_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // A recording of /cam/image_raw messages.
  std::string Write(const std::vector<std::string>& messages) {
    const std::string path = dir_ / "frames.mcap";
    auto w = mcap::Writer::Create(path, {});
    EXPECT_TRUE(w.ok());
    const uint16_t schema = (*w)->AddSchema("sensor_msgs/msg/Image", "ros2msg", "");
    const uint16_t channel = (*w)->AddChannel(schema, "/cam/image_raw", "cdr");
    uint32_t n = 0;
    for (const auto& m : messages) {
      ++n;
      EXPECT_TRUE((*w)->Write(channel, n, n, n, m).ok());
    }
    EXPECT_TRUE((*w)->Close().ok());
    return path;
  }

  std::filesystem::path dir_;
};

constexpr int64_t kT0 = 1795000000123456789;
constexpr int64_t kFrameSpacingNs = 100000000;  // 100 ms

std::string Pixels(char base) {
  return {base, char(base + 1), char(base + 2), char(base + 3), char(base + 4), char(base + 5)};
}

TEST_F(RecordingSourceTest, FramesComeInOrderWithTheirStampsAndPixelsThenTheEnd) {
  const auto path = Write({ImageCdr(kT0, 3, 2, "mono8", Pixels(10)),
                           ImageCdr(kT0 + kFrameSpacingNs, 3, 2, "mono8", Pixels(20))});
  auto source = RecordingSource::Open(path, "/cam", {0, false});
  ASSERT_TRUE(source.ok()) << source.error();
  for (int i = 0; i < 2; ++i) {
    auto frame = (*source)->Next(std::chrono::milliseconds(100));
    ASSERT_TRUE(frame.ok()) << frame.error();
    EXPECT_EQ(frame->sequence, static_cast<uint64_t>(i));
    EXPECT_EQ(frame->capture_time_ns, kT0 + i * kFrameSpacingNs);
    ASSERT_EQ(frame->grey.cols, 3);
    ASSERT_EQ(frame->grey.rows, 2);
    EXPECT_EQ(frame->grey.at<uint8_t>(0, 0), 10 + 10 * i);
    EXPECT_EQ(frame->grey.at<uint8_t>(1, 2), 15 + 10 * i);
  }
  auto end = (*source)->Next(std::chrono::milliseconds(100));
  ASSERT_FALSE(end.ok());
  EXPECT_EQ(end.error().code, ErrorCode::kNotFound);
  EXPECT_TRUE((*source)->ended());
  EXPECT_NE(end.error().message.find("after 2 frames"), std::string::npos) << end.error();
}

TEST_F(RecordingSourceTest, ALoopStartsAgainAndCountsOn) {
  const auto path = Write(
      {ImageCdr(kT0, 3, 2, "mono8", Pixels(10)), ImageCdr(kT0 + 1, 3, 2, "mono8", Pixels(20))});
  auto source = RecordingSource::Open(path, "/cam", {0, true});
  ASSERT_TRUE(source.ok()) << source.error();
  for (int i = 0; i < 5; ++i) {
    auto frame = (*source)->Next(std::chrono::milliseconds(100));
    ASSERT_TRUE(frame.ok()) << frame.error();
    EXPECT_EQ(frame->sequence, static_cast<uint64_t>(i));
    EXPECT_EQ(frame->grey.at<uint8_t>(0, 0), i % 2 == 0 ? 10 : 20);
  }
  EXPECT_FALSE((*source)->ended());
}

TEST_F(RecordingSourceTest, AtTheRecordedPaceTheNextFrameWaitsForItsTime) {
  const auto path = Write({ImageCdr(kT0, 3, 2, "mono8", Pixels(10)),
                           ImageCdr(kT0 + 10 * kFrameSpacingNs, 3, 2, "mono8", Pixels(20))});
  auto source = RecordingSource::Open(path, "/cam", {1, false});
  ASSERT_TRUE(source.ok()) << source.error();
  ASSERT_TRUE((*source)->Next(std::chrono::milliseconds(10)).ok());
  // The second frame is due a second after the first: not within 10 ms.
  auto early = (*source)->Next(std::chrono::milliseconds(10));
  ASSERT_FALSE(early.ok());
  EXPECT_EQ(early.error().code, ErrorCode::kNotFound);
  EXPECT_FALSE((*source)->ended());
  auto later = (*source)->Next(std::chrono::milliseconds(3000));
  ASSERT_TRUE(later.ok()) << later.error();
  EXPECT_EQ(later->sequence, 1u);
}

TEST_F(RecordingSourceTest, FramesThatAreNotWhatTheyClaimAreRefusedWithTheReason) {
  struct Case {
    std::string cdr, expect;
  };
  const std::vector<Case> cases{
      {"garbage", "is not a sensor_msgs/Image"},
      {ImageCdr(kT0, 3, 2, "jpeg", Pixels(1)), "'jpeg' is not one monocle converts"},
      {ImageCdr(kT0, 3, 2, "mono8", Pixels(1).substr(0, 5)), "needs 6 bytes but has 5"},
      {ImageCdr(kT0, 3, 2, "mono8", Pixels(1), 2), "step 2"},
      {ImageCdr(kT0, 0, 0, "mono8", ""), "0x0"},
  };
  for (const auto& c : cases) {
    const auto path = Write({c.cdr});
    auto source = RecordingSource::Open(path, "/cam", {0, false});
    ASSERT_TRUE(source.ok()) << source.error();
    auto frame = (*source)->Next(std::chrono::milliseconds(10));
    ASSERT_FALSE(frame.ok()) << c.expect;
    EXPECT_EQ(frame.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(frame.error().message.find(c.expect), std::string::npos) << frame.error();
    EXPECT_NE(frame.error().message.find("frame 0"), std::string::npos) << frame.error();
  }
}

TEST_F(RecordingSourceTest, ACameraWithoutFramesInTheFileIsNamed) {
  const auto path = Write({ImageCdr(kT0, 3, 2, "mono8", Pixels(10))});
  auto source = RecordingSource::Open(path, "/other", {0, false});
  ASSERT_FALSE(source.ok());
  EXPECT_EQ(source.error().code, ErrorCode::kNotFound);
  EXPECT_NE(source.error().message.find("/other/image_raw"), std::string::npos) << source.error();
  auto bad_rate = RecordingSource::Open(path, "/cam", {-1, false});
  ASSERT_FALSE(bad_rate.ok());
  EXPECT_EQ(bad_rate.error().code, ErrorCode::kInvalidArgument);
}

TEST_F(RecordingSourceTest, ListRecordedCamerasCountsFramesAndSaysWhatIsMissing) {
  const auto path = Write(
      {ImageCdr(kT0, 3, 2, "mono8", Pixels(10)), ImageCdr(kT0 + 1, 3, 2, "mono8", Pixels(20))});
  auto cameras = ListRecordedCameras(path);
  ASSERT_TRUE(cameras.ok()) << cameras.error();
  ASSERT_EQ(cameras->size(), 1u);
  EXPECT_EQ((*cameras)[0].ros_namespace, "/cam");
  EXPECT_EQ((*cameras)[0].id, "cam");  // no status recorded: the namespace's leaf
  EXPECT_EQ((*cameras)[0].frames, 2u);
  EXPECT_TRUE((*cameras)[0].calibration_text.empty());
}

}  // namespace
}  // namespace monocle
