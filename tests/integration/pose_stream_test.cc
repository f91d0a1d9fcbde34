// monocled and a client as separate processes on loopback: the pose stream over DDS agrees
// with the simulated camera's ground truth.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "camera/sim/sim_gv_camera.h"
#include "idl/cli_output.pb.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

constexpr const char* kDomain = "23";

std::string Monocled() {
  std::string bin = testing::MonocleBinary();
  return bin.substr(0, bin.rfind("/client/")) + "/service/monocled";
}

TEST(PoseStreamTest, PosesOverDdsAgreeWithTheSimulatorsGroundTruth) {
  TempDir dir("monocle_pose_stream");
  // Discovery over loopback only, no multicast needed (docker/cyclonedds-loopback.xml).
  const std::string config = std::string(MONOCLE_SOURCE_DIR) + "/docker/cyclonedds-loopback.xml";
  setenv("CYCLONEDDS_URI", ("file://" + config).c_str(), 1);
  testing::ChildProcess monocled(Monocled(), {"--camera", "sim-corner", "--domain", kDomain},
                                 dir / "monocled.log");
  const auto r = RunMonocle(
      dir,
      std::string("corner locate --camera sim-corner --count 5 --json --timeout 30 --domain ") +
          kDomain);
  ASSERT_EQ(r.exit_code, 0) << r.err << testing::ReadFile(dir / "monocled.log");
  EXPECT_EQ(monocled.Stop(), 0) << "monocled stops cleanly on SIGTERM: "
                                << testing::ReadFile(dir / "monocled.log");

  // The ground truth of sim-corner, rendered the same way in this process.
  SimCameraOptions sim;
  sim.serial = "sim-corner";
  sim.trajectory_frames = 8;
  const auto scenes = SimScenes::Render(sim);
  ASSERT_TRUE(scenes.ok());
  std::stringstream lines(r.out);
  int poses = 0;
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok()) << line;
    EXPECT_EQ(out.camera(), "sim-corner");
    ASSERT_FALSE(out.pose().has_error()) << out.pose().error();
    const CornerPose& truth = (*scenes)->CornerPoseFor(out.sequence());
    EXPECT_NEAR(out.pose().x(), truth.x_m, 0.003 * truth.x_m) << "frame " << out.sequence();
    EXPECT_NEAR(out.pose().y(), truth.y_m, 0.003 * truth.y_m) << "frame " << out.sequence();
    EXPECT_NEAR(out.pose().tilt(), truth.tilt_rad, 0.002) << "frame " << out.sequence();
    EXPECT_GT(out.capture_time_ns(), 0);
    ++poses;
  }
  EXPECT_EQ(poses, 5);
}

TEST(PoseStreamTest, NoServiceIsAClearError) {
  TempDir dir("monocle_pose_stream_none");
  const std::string config = std::string(MONOCLE_SOURCE_DIR) + "/docker/cyclonedds-loopback.xml";
  setenv("CYCLONEDDS_URI", ("file://" + config).c_str(), 1);
  const auto r = RunMonocle(dir, "corner locate --camera sim-corner --timeout 1 --domain 24");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is monocled running"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace monocle
