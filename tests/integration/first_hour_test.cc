// What a new user meets in the first hour (issue "The first hour"), each as the user would run
// it: the programs' versions, monocled's printed configuration started as it is, a
// configuration's missing calibration named in full, and the built-in simulated cameras listed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <thread>

#include "monocle/client.h"
#include "tests/integration/cli_process.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::ReadFile;
using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 47;

// Runs monocled to its end with `args`; its exit status, stdout in DIR/out.txt and stderr in
// DIR/err.txt.
int RunMonocled(const TempDir& dir, const std::string& args) {
  const std::string command =
      testing::MonocledBinary() + " " + args + " >" + dir / "out.txt" + " 2>" + dir / "err.txt";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(FirstHourTest, BothProgramsSayTheirVersion) {
  TempDir dir("monocle_first_hour_version");
  EXPECT_EQ(RunMonocled(dir, "--version"), 0) << ReadFile(dir / "err.txt");
  EXPECT_EQ(ReadFile(dir / "out.txt"), "monocled " MONOCLE_VERSION "\n");
  const auto r = RunMonocle(dir, "--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "monocle " MONOCLE_VERSION "\n");
  EXPECT_EQ(RunMonocled(dir, "--help"), 0);
  EXPECT_NE(ReadFile(dir / "out.txt").find("--version"), std::string::npos);
}

// `monocled --print-config > my.pbtxt; monocled --config my.pbtxt` serves the default's cameras,
// from any working directory.
TEST(FirstHourTest, ThePrintedConfigurationStartsAsItIs) {
  TempDir dir("monocle_first_hour_config");
  ASSERT_EQ(RunMonocled(dir, "--print-config --state-dir " + dir / "state"), 0)
      << ReadFile(dir / "err.txt");
  std::filesystem::copy_file(dir / "out.txt", dir / "my.pbtxt");
  testing::UseLoopbackDds();
  testing::ChildProcess monocled(
      testing::MonocledBinary(),
      {"--config", dir / "my.pbtxt", "--domain", std::to_string(kDomain)}, dir / "monocled.log");
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  int streaming = 0;
  for (int i = 0; i < 300 && streaming < 2; ++i) {
    streaming = 0;
    if (auto s = client->status(); s) {
      for (const auto& c : *s) streaming += c.state == CameraState::kStreaming;
    }
    if (streaming < 2) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(streaming, 2) << ReadFile(dir / "monocled.log");
  EXPECT_EQ(monocled.Stop(), 0) << ReadFile(dir / "monocled.log");
}

// A relative calibration path is the configuration file's folder's; the error names the file
// it tried in full.
TEST(FirstHourTest, AMissingCalibrationIsNamedInFull) {
  TempDir dir("monocle_first_hour_missing");
  std::ofstream(dir / "my.pbtxt")
      << "camera { id: \"a\" device: \"sim-corner\" role: CORNER calibration: \"nope.pbtxt\" }\n";
  // As a user types it: the configuration named relative to the working directory.
  const std::string command = "cd " + dir.path().string() + " && " + testing::MonocledBinary() +
                              " --config my.pbtxt 2>" + dir / "err.txt";
  const int status = std::system(command.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_NE(ReadFile(dir / "err.txt").find(dir / "nope.pbtxt"), std::string::npos)
      << ReadFile(dir / "err.txt");
}

TEST(FirstHourTest, CamerasListsTheBuiltInSimulatedCameras) {
  TempDir dir("monocle_first_hour_cameras");
  const auto r = RunMonocle(dir, "cameras");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("built-in simulated cameras, no hardware needed: sim-corner "
                       "sim-corner-realistic sim-floor"),
            std::string::npos)
      << r.out;
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// A misspelled simulated camera fails at once and for good: said in monocled's log, on the
// status topic, and by `monocle status` (the container's healthcheck) with exit status 1.
TEST(FirstHourTest, ACameraThatCannotBeFailsAndSaysWhatThereIs) {
  TempDir dir("monocle_first_hour_typo");
  ASSERT_EQ(RunMonocled(dir, "--print-config --state-dir " + dir / "state"), 0);
  std::string config = ReadFile(dir / "out.txt");
  const auto at = config.find("device: \"sim-floor\"");
  ASSERT_NE(at, std::string::npos) << config;
  config.replace(at, std::string("device: \"sim-floor\"").size(), "device: \"sim-flor\"");
  std::ofstream(dir / "typo.pbtxt") << config;
  testing::UseLoopbackDds();
  testing::ChildProcess monocled(
      testing::MonocledBinary(),
      {"--config", dir / "typo.pbtxt", "--domain", std::to_string(kDomain)}, dir / "monocled.log");
  auto client = Client::open({kDomain, std::chrono::milliseconds(30000)});
  ASSERT_TRUE(client.ok()) << client.error();
  std::optional<CameraStatus> typo;
  for (int i = 0; i < 300 && !(typo && typo->state == CameraState::kFailed); ++i) {
    if (auto s = client->status(); s) {
      for (const auto& c : *s)
        if (c.camera_id == "sim-floor") typo = c;
    }
    if (!(typo && typo->state == CameraState::kFailed))
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(typo.has_value()) << ReadFile(dir / "monocled.log");
  EXPECT_EQ(typo->state, CameraState::kFailed) << typo->last_error;
  EXPECT_NE(typo->last_error.find("'sim-flor' is not a built-in simulated camera (sim-corner, "
                                  "sim-corner-realistic, sim-floor)"),
            std::string::npos)
      << typo->last_error;
  const auto r = RunMonocle(dir, "status --domain " + std::to_string(kDomain) + " --timeout 30");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("camera 'sim-floor' failed: 'sim-flor' is not"), std::string::npos) << r.err;
  EXPECT_EQ(monocled.Stop(), 0) << ReadFile(dir / "monocled.log");
  EXPECT_NE(ReadFile(dir / "monocled.log").find("camera 'sim-floor' failed: 'sim-flor'"),
            std::string::npos)
      << ReadFile(dir / "monocled.log");
}

}  // namespace
}  // namespace monocle
