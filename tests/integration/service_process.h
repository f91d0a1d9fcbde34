// monocled in its own process for integration tests: a configuration file in a temporary
// directory, DDS on loopback only.
#pragma once

#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "tests/integration/cli_process.h"

namespace monocle::testing {

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
// monocled with it; its log is DIR/monocled.log.
inline std::unique_ptr<ChildProcess> StartMonocled(const TempDir& dir, const std::string& config) {
  UseLoopbackDds();
  std::ofstream(dir / "monocled.pbtxt") << config;
  return std::make_unique<ChildProcess>(
      MonocledBinary(), std::vector<std::string>{"--config", dir / "monocled.pbtxt"},
      dir / "monocled.log");
}

}  // namespace monocle::testing
