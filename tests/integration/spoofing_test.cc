// On plain DDS anyone on the network can publish on monocle's topics. A spoofer in its own
// process (tests/integration/spoofer.cc) publishes corner poses on a camera's topic, or a
// status claiming a camera namespace: the client library and the CLI deliver none of its data
// as the camera's and say so, and the real service is clean again once the spoofer has left.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <sstream>
#include <thread>

#include "camera/sim/sim_calibrations.h"
#include "idl/cli_output.pb.h"
#include "monocle/client.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using namespace std::chrono_literals;
using testing::ChildProcess;
using testing::RunMonocle;

constexpr int kDomain = 49;
const char kFakeService[] = "evil-host/666";

class SpoofingTest : public testing::ServiceTest {
 protected:
  SpoofingTest() : ServiceTest("monocle_spoofing") {}
  void SetUp() override {
    ASSERT_TRUE(EnsureSimulatorCalibrations(dir_ / "state").ok());
    ASSERT_NO_FATAL_FAILURE(StartService(kDomain,
                                         "status_period_s: 0.25\n"
                                         "camera { id: \"sim-corner\" device: "
                                         "\"sim-corner\" role: CORNER calibration: "
                                         "\"state/sim-corner.pbtxt\" }\n"
                                         "camera { id: \"sim-floor\" device: "
                                         "\"sim-floor\" role: FLOOR calibration: "
                                         "\"state/sim-floor.pbtxt\" }\n"));
  }
  std::unique_ptr<ChildProcess> Spoof(const std::vector<std::string>& args) {
    const std::string bin = testing::MonocleBinary();
    const std::string spoofer = bin.substr(0, bin.rfind("/client/")) + "/tests/integration/spoofer";
    std::vector<std::string> all{"--domain", std::to_string(kDomain)};
    all.insert(all.end(), args.begin(), args.end());
    return std::make_unique<ChildProcess>(spoofer, all, dir_ / "spoofer.log");
  }
  // The real service's status of `camera` (not the spoofer's).
  std::optional<CameraStatus> RealStatus(const std::string& camera) {
    const auto all = client_->status();
    if (!all) return std::nullopt;
    for (const auto& c : *all)
      if (c.camera_id == camera && c.service != kFakeService) return c;
    return std::nullopt;
  }
};

// Fake corner poses (x = y = z = 42 m) on the camera's own topic, 30 a second: the CLI prints
// only the service's poses and warns of the others; the client library the same.
TEST_F(SpoofingTest, FakePosesOnACamerasTopicAreNotTheCamerasAndAreReported) {
  auto spoofer = Spoof({"poses", "/monocle/sim_corner", "sim-corner", "20"});
  std::this_thread::sleep_for(1s);  // its discovery
  const auto r = RunMonocle(dir_,
                            "corner locate --camera sim-corner --count 25 --json "
                            "--timeout 30 --domain " +
                                std::to_string(kDomain));
  ASSERT_EQ(r.exit_code, 0) << r.err << testing::ReadFile(dir_ / "monocled.log");
  std::stringstream lines(r.out);
  int poses = 0;
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok()) << line;
    ++poses;
    EXPECT_NE(out.pose().x(), 42) << "a spoofed pose printed as the camera's: " << line;
  }
  EXPECT_EQ(poses, 25);
  EXPECT_NE(r.err.find("corner poses not delivered: they came from a participant that does not "
                       "serve it"),
            std::string::npos)
      << r.err;

  std::mutex mutex;
  std::vector<Pose> delivered;
  std::vector<std::string> reports;
  auto sub = client_->subscribe_poses(
      [&](const Pose& p) {
        std::lock_guard<std::mutex> lock(mutex);
        delivered.push_back(p);
      },
      "sim-corner",
      [&](const std::string& why) {
        std::lock_guard<std::mutex> lock(mutex);
        reports.push_back(why);
      });
  ASSERT_TRUE(sub.ok()) << sub.error();
  std::this_thread::sleep_for(3s);
  sub->stop();
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_FALSE(delivered.empty()) << "the service's own poses still come";
  for (const Pose& p : delivered) EXPECT_NE(p.x_m, 42) << "a spoofed pose delivered";
  ASSERT_FALSE(reports.empty());
  EXPECT_NE(reports.front().find("camera 'sim-corner' (/monocle/sim_corner): "), std::string::npos)
      << reports.front();
}

// A fake status claiming the floor camera's namespace: while it is there, clients refuse the
// camera with the conflict rather than mix two sources, and the service notes the claimant;
// once it has left, the service's status is clean within 5 s and the camera answers again.
TEST_F(SpoofingTest, AFakeStatusIsAConflictAndTheServiceIsCleanOnceItLeaves) {
  ASSERT_TRUE(client_->measure("sim-floor", {{640, 900, std::nullopt}}).ok());
  auto spoofer = Spoof({"status", "/monocle/sim_floor", "sim-floor", kFakeService, "4"});
  bool noted = false;
  for (int i = 0; i < 30 && !noted; ++i) {
    std::this_thread::sleep_for(100ms);
    const auto real = RealStatus("sim-floor");
    noted = real && real->last_error.find(kFakeService) != std::string::npos;
  }
  EXPECT_TRUE(noted) << "the service notes the other claimant";
  const auto refused = client_->measure("sim-floor", {{640, 900, std::nullopt}});
  ASSERT_FALSE(refused.ok()) << "two sources for one camera: neither is used";
  EXPECT_NE(refused.error().message.find("is served by 2 monocled"), std::string::npos)
      << refused.error();
  EXPECT_NE(refused.error().message.find(kFakeService), std::string::npos) << refused.error();

  // It leaves as a program does when it ends (its participant closed, not killed): waited
  // for, not signalled, since a SIGTERM during its teardown would kill it mid-goodbye.
  EXPECT_EQ(spoofer->WaitFor(15s), std::optional<int>(0))
      << testing::ReadFile(dir_ / "spoofer.log");
  const auto left = std::chrono::steady_clock::now();
  bool clean = false;
  for (int i = 0; i < 50 && !clean; ++i) {
    std::this_thread::sleep_for(100ms);
    const auto real = RealStatus("sim-floor");
    clean = real && real->last_error.find(kFakeService) == std::string::npos;
  }
  EXPECT_TRUE(clean) << "still noted 5 s after the claimant left: "
                     << RealStatus("sim-floor")->last_error;
  std::cout << "clean "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - left).count()
            << " s after the spoofer left\n";
  const auto answered = client_->measure("sim-floor", {{640, 900, std::nullopt}});
  EXPECT_TRUE(answered.ok()) << answered.error();
  EXPECT_NE(testing::ReadFile(dir_ / "monocled.log").find("is ours alone again"), std::string::npos)
      << testing::ReadFile(dir_ / "monocled.log");
}

// A fake status that copies the real service's id: `monocle status` still sees two services
// on the namespace (they are told apart by participant, not by the id they give), names both
// participants and exits 1.
TEST_F(SpoofingTest, AStatusCopyingTheServiceIdIsStillAConflictNamedByParticipant) {
  const auto real = RealStatus("sim-floor");
  ASSERT_TRUE(real.has_value());
  ASSERT_FALSE(real->participant.empty());
  auto spoofer = Spoof({"status", "/monocle/sim_floor", "sim-floor", real->service, "4"});
  testing::ProcessResult status;
  for (int i = 0; i < 30; ++i) {
    std::this_thread::sleep_for(200ms);
    status = RunMonocle(dir_, "status --json --domain " + std::to_string(kDomain));
    if (status.err.find("is served by 2 monocled") != std::string::npos) break;
  }
  EXPECT_EQ(status.exit_code, 1) << status.out << status.err;
  EXPECT_NE(status.err.find("/monocle/sim_floor is served by 2 monocled (" + real->service +
                            " from participant "),
            std::string::npos)
      << status.err;
  EXPECT_NE(status.err.find(" from participant " + real->participant), std::string::npos)
      << status.err;
  EXPECT_NE(status.out.find("\"participant\":\"" + real->participant + "\""), std::string::npos)
      << status.out;
}

// A participant answering every point query with 42 m, and one publishing a calibration of the
// floor camera far ahead of the service's revision: the client takes neither as the camera's.
TEST_F(SpoofingTest, FakeRepliesAndCalibrationsAreNotTheCameras) {
  std::mutex reports_mutex;
  std::vector<std::string> reports;
  Client::Options options{kDomain, 5s};
  options.on_ignored = [&](const std::string& what) {
    std::lock_guard<std::mutex> lock(reports_mutex);
    reports.push_back(what);
  };
  auto client = Client::open(options);
  ASSERT_TRUE(client.ok()) << client.error();
  const auto reported = [&](const std::string& what) {
    std::lock_guard<std::mutex> lock(reports_mutex);
    for (const auto& r : reports)
      if (r.find(what) != std::string::npos) return true;
    return false;
  };
  ASSERT_TRUE(client->measure("sim-floor", {{640, 900, std::nullopt}}).ok());
  auto replies = Spoof({"replies", "/monocle/sim_floor", "30"});
  std::this_thread::sleep_for(1s);  // its discovery
  // At least 30 queries, and on until the spoofer's replies have come (its discovery takes
  // longer on a busy machine), for at most 15 s.
  const auto give_up = std::chrono::steady_clock::now() + 15s;
  for (int i = 0; i < 30 || (!reported("measure_points replies not taken") &&
                             std::chrono::steady_clock::now() < give_up);
       ++i) {
    const auto r =
        client->measure("sim-floor", {{640, 900, std::nullopt}, {600, 800, std::nullopt}});
    ASSERT_TRUE(r.ok()) << r.error();
    for (const MeasuredPoint& p : *r)
      EXPECT_NE(p.p_robot_m[0], 42) << "a spoofed answer, query " << i;
    std::this_thread::sleep_for(10ms);
  }
  const auto cli = RunMonocle(
      dir_, "floor measure --camera sim-floor 640,900 --domain " + std::to_string(kDomain));
  EXPECT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_EQ(cli.out.find("x=42"), std::string::npos) << cli.out;
  // The spoofer answers each query: its replies reached the client and were reported, not
  // taken, whether they came before the service's or after.
  EXPECT_TRUE(reported("camera 'sim-floor' (/monocle/sim_floor): ")) << "no foreign reply reported";
  EXPECT_TRUE(
      reported("measure_points replies not taken: they came from a participant that "
               "does not serve it"));
  replies.reset();

  auto calibration = Spoof({"calibration", "/monocle/sim_floor", "sim-floor", "30"});
  std::this_thread::sleep_for(1s);
  const auto calibrations = client->calibrations();
  ASSERT_TRUE(calibrations.ok()) << calibrations.error();
  bool seen = false;
  for (const Calibration& c : *calibrations) {
    if (c.camera_id != "sim-floor") continue;
    seen = true;
    EXPECT_LT(c.revision, 1000u) << "the spoofer's calibration";
    EXPECT_NE(c.file, "/evil.pbtxt");
    EXPECT_NE(c.fx, 42);
  }
  EXPECT_TRUE(seen);
  EXPECT_TRUE(
      reported("calibrations not taken: they came from a participant that does not "
               "serve it"));
}

}  // namespace
}  // namespace monocle
