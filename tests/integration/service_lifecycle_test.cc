// monocled's life in its own process: stop signals obeyed at every stage of start-up, files
// that are not regular refused at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "camera/sim/sim_gv_camera.h"
#include "monocle/client.h"
#include "service/io/calibration_file.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::ReadFile;
using testing::TempDir;

constexpr int kDomain = 55;

std::string TwoCameras(const std::string& floor_calibration) {
  return "domain: " + std::to_string(kDomain) +
         "\ncamera { id: \"floor\" device: \"sim-floor\" role: FLOOR calibration: \"" +
         floor_calibration +
         "\" }\n"
         "camera { id: \"corner\" device: \"sim-corner\" role: CORNER calibration: "
         "\"corner.pbtxt\" ceiling_distance_m: 1.6 }\n";
}

void WriteCalibrations(const TempDir& dir) {
  CameraCalibration cal;
  cal.intrinsics = SimIntrinsics(1280, 1024);
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir / "corner.pbtxt", cal).ok());
  cal.floor = FloorCalibration{};
  cal.floor->pose = FloorPose{1.0, 1.9, 0, 0};
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir / "floor.pbtxt", cal).ok());
}

// Issue 14: start-up ignored SIGTERM (for minutes with many cameras). A stop signal at any
// moment of start-up, or just after, ends monocled cleanly (exit 0) within seconds.
TEST(ServiceLifecycleTest, StopSignalIsObeyedAtEveryStageOfStartUp) {
  TempDir dir("monocle_lifecycle_stop");
  WriteCalibrations(dir);
  int during_start_up = 0;
  for (const int delay_ms : {0, 5, 20, 50, 100, 200, 400, 700, 1000, 1500, 2500}) {
    auto monocled = testing::StartMonocled(dir, TwoCameras("floor.pbtxt"));
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    const int status = monocled->StopWithin(std::chrono::seconds(10));
    const std::string log = ReadFile(dir / "monocled.log");
    EXPECT_NE(status, -2) << "SIGTERM after " << delay_ms << " ms was not obeyed in 10 s: " << log;
    // Before main() runs (exec, loading the libraries) the signal's default action ends the
    // process: nothing was started, nothing is logged. From main() on, it is a clean stop.
    if (status == -1 && log.empty()) continue;
    EXPECT_EQ(status, 0) << "SIGTERM after " << delay_ms << " ms: " << log;
    EXPECT_NE(log.find("stopped"), std::string::npos) << delay_ms << " ms: " << log;
    during_start_up += log.find("stopped during start-up") != std::string::npos;
  }
  // The service listens for a second before serving: some signals land in start-up.
  EXPECT_GE(during_start_up, 1);
}

// Issue 14: a calibration path naming /dev/zero was read until the kernel killed monocled at
// 23 GB. It is refused at once, naming the camera, the file and what to do.
TEST(ServiceLifecycleTest, ADeviceAsCalibrationFileIsRefusedAtOnce) {
  TempDir dir("monocle_lifecycle_devzero");
  WriteCalibrations(dir);
  auto monocled = testing::StartMonocled(dir, TwoCameras("/dev/zero"));
  // It exits by itself with an error; waiting on it must not need the signal.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (ReadFile(dir / "monocled.log").find("error") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const int status = monocled->StopWithin(std::chrono::seconds(10));
  const std::string log = ReadFile(dir / "monocled.log");
  EXPECT_EQ(status, 1) << log;
  EXPECT_NE(log.find("camera 'floor'"), std::string::npos) << log;
  EXPECT_NE(log.find("/dev/zero': not a regular file"), std::string::npos) << log;
}

// Issue 14: an unknown GenICam feature was retried forever (state reconnecting, the error
// renewed every 2 s). A configuration error is permanent: reported once, state failed.
TEST(ServiceLifecycleTest, AConfigurationErrorIsReportedOnceAsFailed) {
  TempDir dir("monocle_lifecycle_failed");
  WriteCalibrations(dir);
  auto monocled = testing::StartMonocled(
      dir, "domain: " + std::to_string(kDomain) +
               "\nstatus_period_s: 0.25\n"
               "camera { id: \"floor\" device: \"sim-floor\" role: FLOOR calibration: "
               "\"floor.pbtxt\" }\n"
               "camera { id: \"misconfigured\" device: \"sim-floor\" role: FLOOR calibration: "
               "\"floor.pbtxt\" feature { name: \"NoSuchFeature\" value: \"1\" } }\n");
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  auto* client_ = &*client;
  std::optional<CameraStatus> first;
  for (int attempt = 0; attempt < 120 && !first; ++attempt) {
    const auto status = client_->status();
    ASSERT_TRUE(status.ok()) << status.error() << "\n" << ReadFile(dir / "monocled.log");
    for (const auto& s : *status)
      if (s.camera_id == "misconfigured" && s.state == CameraState::kFailed) first = s;
    if (!first) std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  ASSERT_TRUE(first.has_value()) << ReadFile(dir / "monocled.log");
  EXPECT_NE(first->last_error.find("unknown GenICam feature 'NoSuchFeature'"), std::string::npos)
      << first->last_error;
  // Not retried: three seconds on (the retry back-off is at most 2 s), the same error, from
  // the same moment, and still failed.
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const auto later = client_->status();
  ASSERT_TRUE(later.ok());
  bool seen = false;
  for (const auto& s : *later) {
    if (s.camera_id != "misconfigured") continue;
    seen = true;
    EXPECT_EQ(s.state, CameraState::kFailed);
    EXPECT_EQ(s.last_error_ns, first->last_error_ns) << "the error was renewed: retried";
    EXPECT_EQ(s.frames, 0u);
  }
  EXPECT_TRUE(seen);
  // The other cameras are unaffected.
  EXPECT_TRUE(client_->measure("floor", {{640, 900, {}}}).ok());
  EXPECT_EQ(monocled->StopWithin(std::chrono::seconds(10)), 0) << ReadFile(dir / "monocled.log");
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

double ResidentMb(pid_t pid) {
  std::istringstream status(ReadFile("/proc/" + std::to_string(pid) + "/status"));
  for (std::string line; std::getline(status, line);)
    if (line.starts_with("VmRSS:")) return std::stod(line.substr(6)) / 1024;
  return -1;
}

// Issue 62: on its embedded default (sim-corner driving its loop, sim-floor) monocled tracks
// the corner live and fits in 64 MB resident once started (it held 177-183 MB: rendering's
// working memory kept by the allocator, the renderer's cached undistortion grid).
TEST(ServiceLifecycleTest, TheEmbeddedDefaultTracksLiveAndFitsIn64Mb) {
  if (testing::kUnderAddressSanitizer || testing::kThreadSanitizer)
    GTEST_SKIP() << "a sanitizer's shadow memory is part of the resident size";
  TempDir dir("monocle_lifecycle_memory");
  const int domain = kDomain + 1;
  testing::ChildProcess monocled(testing::MonocledBinary(),
                                 {"--domain", std::to_string(domain), "--state-dir", dir / "state"},
                                 dir / "monocled.log");
  const auto poses = testing::RunMonocle(
      dir, "corner locate --camera sim-corner --count 20 --timeout 30 --domain " +
               std::to_string(domain));
  ASSERT_EQ(poses.exit_code, 0) << poses.err << ReadFile(dir / "monocled.log");
  int tracked = 0;
  std::istringstream lines(poses.out);
  for (std::string line; std::getline(lines, line);) tracked += line.ends_with("tracked");
  EXPECT_GE(tracked, 15) << "the driving simulated camera should be tracked frame to frame:\n"
                         << poses.out;
  const auto point = testing::RunMonocle(
      dir, "floor measure --camera sim-floor 640,900 --domain " + std::to_string(domain));
  EXPECT_EQ(point.exit_code, 0) << point.err;
  double largest_mb = 0;
  for (int i = 0; i < 30; ++i) {  // 3 s of samples: the largest counts
    largest_mb = std::max(largest_mb, ResidentMb(monocled.pid()));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_GT(largest_mb, 0);
  EXPECT_LE(largest_mb, 64) << "monocled's resident size after start-up";
}

}  // namespace
}  // namespace monocle
