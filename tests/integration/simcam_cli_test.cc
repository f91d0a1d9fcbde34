// `monocle simcam` in its own process, `monocle snapshot` and `monocle corner locate` in
// others: the simulated camera as a user runs it, over the real GigE Vision path.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "idl/cli_output.pb.h"
#include "service/vision/edge_profile.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

TEST(SimcamCliTest, SnapshotOfTheSimulatedCameraGivesItsGroundTruthPose) {
  TempDir dir("monocle_simcam_cli");
  testing::ChildProcess simcam(
      testing::MonocleBinary(),
      {"simcam", "--scene", "corner", "--width", "640", "--height", "512", "--frames", "4",
       "--truth", dir / "truth.jsonl", "--calibration-out", dir / "sim.pbtxt"},
      dir / "simcam.log");
  // Wait until the simulator wrote its calibration file (it serves right after).
  for (int i = 0; i < 100 && !std::ifstream(dir / "sim.pbtxt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::ifstream(dir / "sim.pbtxt").good()) << testing::ReadFile(dir / "simcam.log");
  const auto snap = RunMonocle(dir, "snapshot 127.0.0.1 --out " + dir / "snap.png");
  ASSERT_EQ(snap.exit_code, 0) << snap.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(snap.out, m, std::regex(R"(frame (\d+) 640x512)"))) << snap.out;
  const uint64_t id = std::stoull(m[1]);

  const auto located = RunMonocle(
      dir, "corner locate " + dir / "snap.png" + " --calibration " + dir / "sim.pbtxt" + " --json");
  ASSERT_EQ(located.exit_code, 0) << located.err << located.out;
  // The truth file: pose i for frame ids with id mod 4 == i.
  std::ifstream truth(dir / "truth.jsonl");
  std::string line, wanted;
  while (std::getline(truth, line)) {
    if (line.find("\"frame_id_mod\":" + std::to_string(id % 4) + ",") != std::string::npos)
      wanted = line;
  }
  ASSERT_FALSE(wanted.empty());
  auto number = [](const std::string& json, const std::string& key) {
    std::smatch n;
    EXPECT_TRUE(std::regex_search(json, n, std::regex("\"" + key + "\":(-?[0-9.e+-]+)")))
        << key << " in " << json;
    return std::stod(n[1]);
  };
  proto::CornerOutput got;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(located.out, &got).ok()) << located.out;
  EXPECT_NEAR(got.x(), number(wanted, "x"), 0.01 * number(wanted, "x"));
  EXPECT_NEAR(got.y(), number(wanted, "y"), 0.01 * number(wanted, "y"));
  EXPECT_NEAR(got.tilt(), number(wanted, "tilt"), 0.005);
  EXPECT_EQ(simcam.Stop(), 0) << "simcam exits cleanly on SIGTERM";
}

// `simcam --realistic --raw`: the white room as a machine-vision camera delivers it, without
// the JPEG step. The look is printed; the snapshot (over GigE Vision) carries its full pixel
// noise, which JPEG would have cut 2-5x, and the locator reads the same noise.
TEST(SimcamCliTest, ARawRealisticCameraSendsItsSensorNoise) {
  TempDir dir("monocle_simcam_raw");
  testing::ChildProcess simcam(
      testing::MonocleBinary(),
      {"simcam", "--scene", "corner", "--frames", "2", "--realistic", "--raw", "--look-seed", "4",
       "--calibration-out", dir / "sim.pbtxt"},
      dir / "simcam.log");
  for (int i = 0; i < 100 && !std::ifstream(dir / "sim.pbtxt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::ifstream(dir / "sim.pbtxt").good()) << testing::ReadFile(dir / "simcam.log");
  const std::string log = testing::ReadFile(dir / "simcam.log");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex(R"(noise ([0-9.]+), jpeg (\d+)\})"))) << log;
  const double sensor_noise = std::stod(m[1]);
  EXPECT_EQ(m[2].str(), "0") << log;
  const auto snap = RunMonocle(dir, "snapshot 127.0.0.1 --out " + dir / "snap.png");
  ASSERT_EQ(snap.exit_code, 0) << snap.err;
  const cv::Mat frame = cv::imread(dir / "snap.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(frame.empty());
  EXPECT_NEAR(EstimateNoiseSigma(frame), sensor_noise, 0.2 * sensor_noise) << "pixel noise";
  const auto located = RunMonocle(
      dir, "corner locate " + dir / "snap.png" + " --calibration " + dir / "sim.pbtxt" + " --json");
  ASSERT_EQ(located.exit_code, 0) << located.err << located.out;
  proto::CornerOutput got;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(located.out, &got).ok()) << located.out;
  EXPECT_NEAR(got.noise_grey(), sensor_noise, 0.25 * sensor_noise) << located.out;
  EXPECT_EQ(simcam.Stop(), 0);
}

TEST(SimcamCliTest, SnapshotOfAnUnknownCameraSaysSo) {
  TempDir dir("monocle_snapshot_cli");
  const auto r = RunMonocle(dir, "snapshot no-such-camera --out " + dir / "x.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no camera 'no-such-camera'"), std::string::npos) << r.err;
}

TEST(SimcamCliTest, ASerialTooLongForTheCameraIsRefusedWithTheLimit) {
  TempDir dir("monocle_simcam_serial");
  const auto r = RunMonocle(dir, "simcam --scene floor --serial ABCDEFGHIJKLMNOPQRSTU");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("must be 1 to 15 characters"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("CRITICAL"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace monocle
