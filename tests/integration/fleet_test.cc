// Several robots on one DDS domain: monocled processes in their own processes, each with a
// floor camera named "front" and a calibration of its own. Namespaces keep them apart; two
// services claiming one namespace are reported by the services, the client and monocle
// status instead of being mixed.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <thread>

#include "monocle/client.h"
#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::ReadFile;
using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 43;

// A robot whose floor camera is `height_m` above the floor, served under `ns`.
// `discovery_wait_s`: how long it listens for services already there before serving.
std::unique_ptr<testing::ChildProcess> StartRobot(const TempDir& dir, const std::string& ns,
                                                  double height_m, double discovery_wait_s = 1) {
  CameraCalibration cal;
  cal.intrinsics = testing::PaperCamera();
  cal.floor = FloorCalibration{};
  cal.floor->pose = FloorPose{height_m, 2.0595, 0.0698, 0.0262};
  cal.floor->covariance = FloorCovariance::Identity() * 1e-8;
  EXPECT_TRUE(SaveCalibrationFileAtomically(dir / "front.pbtxt", cal).ok());
  return testing::StartMonocled(dir, "domain: " + std::to_string(kDomain) +
                                         "\ndiscovery_wait_s: " + std::to_string(discovery_wait_s) +
                                         "\ncamera { id: \"front\" device: \"sim-floor\" role: "
                                         "FLOOR calibration: \"front.pbtxt\" ros_namespace: \"" +
                                         ns + "\" }\n");
}

// Waits until the client sees `n` cameras.
std::vector<CameraStatus> WaitForCameras(Client& client, size_t n) {
  std::vector<CameraStatus> cameras;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(40);
  while (std::chrono::steady_clock::now() < deadline) {
    auto s = client.status();
    if (s && s->size() >= n) return *s;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return cameras;
}

TEST(FleetTest, NamespacesKeepRobotsApartAndAnIdOnTwoRobotsIsAmbiguous) {
  TempDir a("monocle_fleet_a"), b("monocle_fleet_b");
  auto robot1 = StartRobot(a, "/robot1/monocle/front", 1.05);
  auto robot2 = StartRobot(b, "/robot2/monocle/front", 0.80);
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  const auto cameras = WaitForCameras(*client, 2);
  ASSERT_EQ(cameras.size(), 2u) << ReadFile(a / "monocled.log") << ReadFile(b / "monocled.log");
  EXPECT_EQ(cameras[0].ros_namespace, "/robot1/monocle/front");
  EXPECT_EQ(cameras[1].ros_namespace, "/robot2/monocle/front");
  EXPECT_NE(cameras[0].service, cameras[1].service);
  EXPECT_EQ(DuplicateCameras(cameras), "");

  // The same pixel on each robot: the lower camera sees it nearer.
  const auto p1 = client->measure("/robot1/monocle/front", {{640, 900, std::nullopt}});
  const auto p2 = client->measure("/robot2/monocle/front", {{640, 900, std::nullopt}});
  ASSERT_TRUE(p1.ok()) << p1.error();
  ASSERT_TRUE(p2.ok()) << p2.error();
  ASSERT_TRUE((*p1)[0].ok() && (*p2)[0].ok());
  EXPECT_NEAR((*p2)[0].p_robot_m[1] / (*p1)[0].p_robot_m[1], 0.80 / 1.05, 1e-6);

  const auto ambiguous = client->measure("front", {{640, 900, std::nullopt}});
  ASSERT_FALSE(ambiguous.ok());
  EXPECT_EQ(ambiguous.error().code, ClientError::Code::kInvalidRequest);
  EXPECT_NE(ambiguous.error().message.find("several robots"), std::string::npos)
      << ambiguous.error();
  EXPECT_NE(ambiguous.error().message.find("/robot2/monocle/front"), std::string::npos);

  // monocle status lists both, by namespace, and exits 0.
  const auto status = RunMonocle(a, "status --timeout 30 --domain " + std::to_string(kDomain));
  EXPECT_EQ(status.exit_code, 0) << status.err;
  EXPECT_NE(status.out.find("/robot1/monocle/front"), std::string::npos) << status.out;
  EXPECT_NE(status.out.find("/robot2/monocle/front"), std::string::npos) << status.out;
  EXPECT_EQ(robot1->Stop(), 0) << ReadFile(a / "monocled.log");
  EXPECT_EQ(robot2->Stop(), 0) << ReadFile(b / "monocled.log");
}

// Two services that start at the same moment (here: neither listens before serving) both
// serve; they are reported, and clients refuse the namespace rather than mix answers.
TEST(FleetTest, TwoServicesOnOneNamespaceAreReportedNotMixed) {
  TempDir a("monocle_fleet_dup_a"), b("monocle_fleet_dup_b");
  auto first = StartRobot(a, "/robot1/monocle/front", 1.05, 0);
  auto second = StartRobot(b, "/robot1/monocle/front", 0.80, 0);
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  const auto cameras = WaitForCameras(*client, 2);
  ASSERT_EQ(cameras.size(), 2u);
  const std::string clash = DuplicateCameras(cameras);
  EXPECT_NE(clash.find("/robot1/monocle/front is served by 2 monocled"), std::string::npos)
      << clash;

  // Requests to that camera are refused with the reason, whichever name is used.
  for (const char* name : {"front", "/robot1/monocle/front"}) {
    const auto r = client->measure(name, {{640, 900, std::nullopt}});
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_EQ(r.error().code, ClientError::Code::kInvalidRequest);
    EXPECT_NE(r.error().message.find("served by 2 monocled"), std::string::npos) << r.error();
  }

  const auto status = RunMonocle(a, "status --timeout 30 --domain " + std::to_string(kDomain));
  EXPECT_EQ(status.exit_code, 1) << status.out << status.err;
  EXPECT_NE(status.err.find("served by 2 monocled"), std::string::npos) << status.err;

  // Each service notices the other within a status period or two, and says so in its log.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  bool logged = false;
  while (!logged && std::chrono::steady_clock::now() < deadline) {
    logged = ReadFile(a / "monocled.log").find("is also served by monocled") != std::string::npos &&
             ReadFile(b / "monocled.log").find("is also served by monocled") != std::string::npos;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_TRUE(logged) << ReadFile(a / "monocled.log") << ReadFile(b / "monocled.log");
  EXPECT_EQ(first->Stop(), 0);
  EXPECT_EQ(second->Stop(), 0);
}

// Issue 14: a second monocled with the same camera namespace started silently and answers
// alternated between the two calibrations. A newcomer now refuses the namespace: one service
// answers, both say so.
TEST(FleetTest, ANewcomerRefusesANamespaceAlreadyServed) {
  TempDir a("monocle_fleet_new_a"), b("monocle_fleet_new_b");
  auto first = StartRobot(a, "/robot1/monocle/front", 1.05);
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  ASSERT_EQ(WaitForCameras(*client, 1).size(), 1u) << ReadFile(a / "monocled.log");
  const auto before = client->measure("/robot1/monocle/front", {{640, 900, std::nullopt}});
  ASSERT_TRUE(before.ok() && (*before)[0].ok());

  auto second = StartRobot(b, "/robot1/monocle/front", 0.80);
  // The newcomer says it refused, and why, in its log and in its camera's status.
  std::vector<CameraStatus> cameras;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  std::optional<CameraStatus> refused;
  while (!refused && std::chrono::steady_clock::now() < deadline) {
    cameras = WaitForCameras(*client, 2);
    for (const auto& c : cameras)
      if (c.state == CameraState::kFailed) refused = c;
    if (!refused) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_TRUE(refused.has_value()) << ReadFile(b / "monocled.log");
  EXPECT_NE(refused->last_error.find("already served by monocled"), std::string::npos)
      << refused->last_error;
  EXPECT_NE(ReadFile(b / "monocled.log").find("already served by monocled"), std::string::npos)
      << ReadFile(b / "monocled.log");
  // Its start-up list of served cameras (with their ROS 2 services) leaves the refused out.
  EXPECT_EQ(ReadFile(b / "monocled.log").find("ROS 2 /robot1/monocle/front/{"), std::string::npos)
      << ReadFile(b / "monocled.log");
  EXPECT_NE(ReadFile(a / "monocled.log").find("ROS 2 /robot1/monocle/front/{"), std::string::npos)
      << ReadFile(a / "monocled.log");
  EXPECT_EQ(DuplicateCameras(cameras), "");

  // Every answer comes from the first service's calibration (1.05 m), none from the
  // newcomer's (0.80 m).
  for (int i = 0; i < 20; ++i) {
    const auto p = client->measure("front", {{640, 900, std::nullopt}});
    ASSERT_TRUE(p.ok()) << p.error();
    ASSERT_TRUE((*p)[0].ok());
    EXPECT_NEAR((*p)[0].p_robot_m[1], (*before)[0].p_robot_m[1], 1e-9) << i;
  }
  // The refused camera is a failed one: `monocle status` lists it and exits with 1, naming it.
  const auto status = RunMonocle(a, "status --timeout 30 --domain " + std::to_string(kDomain));
  EXPECT_EQ(status.exit_code, 1) << status.err;
  EXPECT_NE(status.out.find("failed"), std::string::npos) << status.out;
  EXPECT_NE(status.err.find("camera 'front' failed: not served"), std::string::npos) << status.err;

  // The first service notices the newcomer and says so in its log and its camera's status.
  bool noticed = false;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!noticed && std::chrono::steady_clock::now() < until) {
    auto s = client->status();
    if (s) {
      for (const auto& c : *s)
        noticed |= c.state == CameraState::kStreaming &&
                   c.last_error.find("also claims camera namespace") != std::string::npos;
    }
    if (!noticed) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_TRUE(noticed);
  EXPECT_NE(ReadFile(a / "monocled.log").find("also claims camera namespace"), std::string::npos)
      << ReadFile(a / "monocled.log");
  EXPECT_EQ(second->Stop(), 0) << ReadFile(b / "monocled.log");
  EXPECT_EQ(first->Stop(), 0) << ReadFile(a / "monocled.log");
}

}  // namespace
}  // namespace monocle
