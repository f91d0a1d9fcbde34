// The example hall's drive served by the simulated GigE Vision camera (`monocle simcam
// --scene room`), and monocled's camera configured for it: shared by the tests of poses in a
// room map.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "tests/integration/service_process.h"

namespace monocle::testing {

inline const std::string kRoomExamples = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/";

// Starts the drive at `fps` frames a second with the realistic look of `look_seed`; its
// calibration is written to DIR/sim.pbtxt once the frames are rendered (minutes under
// ThreadSanitizer). Call under ASSERT_NO_FATAL_FAILURE.
inline void StartRoomDrive(const TempDir& dir, const std::string& look_seed, const std::string& fps,
                           std::unique_ptr<ChildProcess>* simcam) {
  *simcam = std::make_unique<ChildProcess>(
      MonocleBinary(),
      std::vector<std::string>{"simcam", "--scene", "room", "--map",
                               kRoomExamples + "room_map.pbtxt", "--mount",
                               kRoomExamples + "camera_mount.pbtxt", "--trajectory",
                               kRoomExamples + "drive.txt", "--realistic", "--look-seed", look_seed,
                               "--fps", fps, "--calibration-out", dir / "sim.pbtxt"},
      dir / "simcam.log");
  const int wait_100ms = kThreadSanitizer ? 3000 : 600;
  for (int i = 0; i < wait_100ms && !std::ifstream(dir / "sim.pbtxt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(std::ifstream(dir / "sim.pbtxt").good()) << ReadFile(dir / "simcam.log");
}

// monocled's camera "front" on that drive: the example map, the example mount
// (idl/examples/camera_mount.pbtxt) and the drive's start as the initial pose.
inline std::string RoomDriveCameraConfig() {
  return R"(
discovery_wait_s: 0.2
camera {
  id: "front"
  device: "127.0.0.1"
  role: CORNER
  calibration: "sim.pbtxt"
  room_map: ")" +
         kRoomExamples + R"(room_map.pbtxt"
  initial_pose: [1.4, 1.3, -20]
  mount {
    base_frame: "base_link"
    translation_m: [0.1, 0, 0.4]
    rotation_xyzw: [-0.2988362, 0.2988362, -0.6408564, 0.6408564]
  }
}
)";
}

}  // namespace monocle::testing
