// monocled in its own process for integration tests: a configuration file in a temporary
// directory, DDS on loopback only.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "monocle/client.h"
#include "tests/integration/cli_process.h"

namespace monocle::testing {

// A ThreadSanitizer build (MONOCLE_TSAN, CMakeLists.txt): every memory access instrumented,
// the service several times slower. Tests that count work done in a time window say so.
#if defined(MONOCLE_TSAN)
inline constexpr bool kThreadSanitizer = true;
#else
inline constexpr bool kThreadSanitizer = false;
#endif

// Discovery over loopback only, no multicast needed (docker/cyclonedds-loopback.xml). Set
// before the first DDS participant; child processes inherit it.
inline void UseLoopbackDds() {
  const std::string config = std::string(MONOCLE_SOURCE_DIR) + "/docker/cyclonedds-loopback.xml";
  setenv("CYCLONEDDS_URI", ("file://" + config).c_str(), 1);
}

inline std::string MonocledBinary() {
  const std::string bin = MonocleBinary();
  return bin.substr(0, bin.rfind("/client/")) + "/service/monocled";
}

// Writes `config` (text protobuf, idl/service_config.proto) to DIR/monocled.pbtxt and starts
// monocled with it (and `extra_args`); its log is DIR/monocled.log.
inline std::unique_ptr<ChildProcess> StartMonocled(
    const TempDir& dir, const std::string& config,
    const std::vector<std::string>& extra_args = {}) {
  UseLoopbackDds();
  std::ofstream(dir / "monocled.pbtxt") << config;
  std::vector<std::string> args{"--config", dir / "monocled.pbtxt"};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  return std::make_unique<ChildProcess>(MonocledBinary(), args, dir / "monocled.log");
}

// A monocled (StartService) and a client of it; the service must stop cleanly after each
// test. Call StartService under ASSERT_NO_FATAL_FAILURE in SetUp.
class ServiceTest : public ::testing::Test {
 protected:
  explicit ServiceTest(const std::string& dir_name) : dir_(dir_name) {}

  // `cameras`: the camera { ... } entries (and other fields) of the configuration.
  void StartService(int domain, const std::string& cameras,
                    const std::vector<std::string>& extra_args = {}) {
    monocled_ =
        StartMonocled(dir_, "domain: " + std::to_string(domain) + "\n" + cameras, extra_args);
    auto client = Client::open({domain, std::chrono::milliseconds(30000)});
    ASSERT_TRUE(client.ok()) << client.error();
    client_.emplace(std::move(client).value());
  }
  void TearDown() override {
    if (monocled_) {
      EXPECT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
    }
  }

  TempDir dir_;
  std::unique_ptr<ChildProcess> monocled_;
  std::optional<Client> client_;
};

}  // namespace monocle::testing
