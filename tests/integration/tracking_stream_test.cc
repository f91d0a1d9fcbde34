// The realistic simulated GigE Vision camera (`monocle simcam --realistic`, a white-painted
// room) driving slowly past a corner, monocled tracking the corner from frame to frame, and
// `monocle corner locate --camera` in its own process: tracked poses agree with the ground
// truth as well as detected ones, and every pose says which it was. The detected reference is
// a full detection of each of the same frames (rendered here as simcam renders them): the
// stream itself detects only the first frame or two.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "camera/render/corner_renderer.h"
#include "camera/sim/sim_gv_camera.h"
#include "idl/cli_output.pb.h"
#include "service/vision/corner_locator.h"
#include "tests/integration/live_poses.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 27;
constexpr int kFrames = 30;

TEST(TrackingStreamTest, TrackedPosesAgreeWithTheTruthAsWellAsDetectedOnes) {
  TempDir dir("monocle_tracking_stream");
  // 1 cm and 0.2 degrees of pan per frame, then back to the start (a jump: detected).
  std::vector<std::array<double, 6>> truth;
  {
    std::ofstream trajectory(dir / "trajectory.txt");
    for (int i = 0; i < kFrames; ++i) {
      truth.push_back({1.8 + 0.01 * i, 2.2 - 0.004 * i, 1.6, 2.45 + 0.0035 * i, 0.95, 0.05});
      const auto& p = truth.back();
      trajectory << p[0] << "," << p[1] << "," << p[2] << "," << p[3] << "," << p[4] << "," << p[5]
                 << "\n";
    }
  }
  testing::ChildProcess simcam(
      testing::MonocleBinary(),
      {"simcam", "--scene", "corner", "--realistic", "--look-seed", "4", "--fps", "15",
       "--trajectory", dir / "trajectory.txt", "--calibration-out", dir / "sim.pbtxt"},
      dir / "simcam.log");
  // simcam renders its 30 realistic frames before it serves (and writes the calibration);
  // under ThreadSanitizer that takes minutes, not seconds.
  const int wait_100ms = testing::kThreadSanitizer ? 3000 : 300;
  for (int i = 0; i < wait_100ms && !std::ifstream(dir / "sim.pbtxt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::ifstream(dir / "sim.pbtxt").good()) << testing::ReadFile(dir / "simcam.log");
  auto monocled = testing::StartMonocled(dir, "domain: " + std::to_string(kDomain) + R"(
camera { id: "ceiling" device: "127.0.0.1" role: CORNER calibration: "sim.pbtxt" }
)");
  const auto r = RunMonocle(dir,
                            "corner locate --camera ceiling --count 45 --json --timeout 30 "
                            "--domain " +
                                std::to_string(kDomain));
  ASSERT_EQ(r.exit_code, 0) << r.err << testing::ReadFile(dir / "monocled.log");
  std::vector<double> tracked, streamed_detected;
  std::stringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok()) << line;
    ASSERT_FALSE(out.pose().has_error()) << out.pose().error();
    const auto& t = truth[out.sequence() % kFrames];
    const double error =
        std::hypot(out.pose().x() - t[0], out.pose().y() - t[1]) / std::hypot(t[0], t[1]);
    EXPECT_LT(error, 0.01) << line;
    EXPECT_NEAR(out.pose().tilt(), t[4], 0.1 * M_PI / 180) << line;
    ASSERT_TRUE(out.pose().source() == "tracked" || out.pose().source() == "detected") << line;
    (out.pose().source() == "tracked" ? tracked : streamed_detected).push_back(error);
  }
  EXPECT_EQ(monocled->Stop(), 0) << testing::ReadFile(dir / "monocled.log");
  EXPECT_EQ(simcam.Stop(), 0);
  ASSERT_GE(tracked.size(), 20u) << "most frames follow the previous one";
  ASSERT_GE(streamed_detected.size(), 1u) << "the first frame (and the jump back) are detected";
  // Every frame of the trajectory detected in full, as simcam rendered it (its look, its
  // noise seeds).
  SimCameraOptions sim;
  sim.realistic = true;
  sim.look_seed = 4;
  const CameraIntrinsics k = SimIntrinsics(sim.width, sim.height);
  std::vector<double> detected;
  for (int i = 0; i < kFrames; ++i) {
    const auto& t = truth[i];
    const CornerPose pose{t[0], t[1], t[2], t[3], t[4], t[5]};
    CornerScene scene;
    scene.noise_sigma = sim.noise_sigma;
    scene.seed = 100 + i;
    scene.realistic = SimRealisticLook(sim, k);
    const auto got = LocateCorner(RenderCornerScene(k, pose, scene), k, t[2]);
    ASSERT_TRUE(got.ok()) << got.error();
    detected.push_back(std::hypot(got->pose.x_m - t[0], got->pose.y_m - t[1]) /
                       std::hypot(t[0], t[1]));
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::cout << tracked.size() << " tracked, median error " << 100 * median(tracked) << " %; "
            << detected.size() << " frames detected in full, median " << 100 * median(detected)
            << " % (the stream detected " << streamed_detected.size() << ")\n";
  EXPECT_LT(median(tracked), 0.003);
  EXPECT_LT(median(tracked), 1.5 * median(detected) + 0.0005);
}

// A camera mounted rolled 52 degrees, streamed through monocled: its poses are flagged
// "rolled" with the default limit, and not once its calibration file says how far the mount
// may roll (corner { max_swing }), read by the service's camera worker.
TEST(TrackingStreamTest, AMountRolledFurtherThanUsualIsAcceptedWhenItsCalibrationSaysSo) {
  TempDir dir("monocle_rolled_stream");
  std::ofstream(dir / "trajectory.txt") << "2,1.5,1.6,2.2143,0.9,0.9\n";
  testing::ChildProcess simcam(testing::MonocleBinary(),
                               {"simcam", "--scene", "corner", "--fps", "15", "--trajectory",
                                dir / "trajectory.txt", "--calibration-out", dir / "sim.pbtxt"},
                               dir / "simcam.log");
  const int wait_100ms = testing::kThreadSanitizer ? 3000 : 300;
  for (int i = 0; i < wait_100ms && !std::ifstream(dir / "sim.pbtxt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::ifstream(dir / "sim.pbtxt").good()) << testing::ReadFile(dir / "simcam.log");
  std::string calibration = testing::ReadFile(dir / "sim.pbtxt");
  const size_t corner = calibration.find("corner {");
  ASSERT_NE(corner, std::string::npos) << calibration;
  calibration.insert(corner + std::string("corner {").size(), "\n  max_swing: 1.2");
  std::ofstream(dir / "rolled.pbtxt") << calibration;

  for (const std::string file : {"sim.pbtxt", "rolled.pbtxt"}) {
    SCOPED_TRACE(file);
    auto monocled = testing::StartMonocled(
        dir, "domain: " + std::to_string(kDomain) +
                 "\ncamera { id: \"ceiling\" device: \"127.0.0.1\" role: CORNER calibration: \"" +
                 file + "\" }\n");
    const auto poses = testing::ReadLivePoses(dir, "ceiling", 3, kDomain);
    for (const proto::LivePoseOutput& out : poses) {
      const std::string line = out.ShortDebugString();
      ASSERT_FALSE(out.pose().has_error()) << out.pose().error();
      EXPECT_NEAR(out.pose().swing(), 0.9, 0.005) << line;
      EXPECT_NEAR(out.pose().x(), 2.0, 0.02) << line;
      if (file == "sim.pbtxt") {
        EXPECT_TRUE(out.pose().suspect()) << line;
        EXPECT_NE(out.pose().suspect_reason().find("rolled"), std::string::npos) << line;
      } else {
        EXPECT_FALSE(out.pose().suspect()) << line;
      }
    }
    EXPECT_EQ(poses.size(), 3u);
    EXPECT_EQ(monocled->Stop(), 0) << testing::ReadFile(dir / "monocled.log");
  }
  EXPECT_EQ(simcam.Stop(), 0);
}

}  // namespace
}  // namespace monocle
