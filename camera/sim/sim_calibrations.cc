#include "camera/sim/sim_calibrations.h"

#include <filesystem>

#include "camera/sim/sim_gv_camera.h"
#include "service/io/calibration_file.h"

namespace monocle {

Status EnsureSimulatorCalibrations(const std::string& state_dir) {
  std::error_code ec;
  std::filesystem::create_directories(state_dir, ec);
  if (ec) {
    return MakeError(ErrorCode::kIo,
                     "cannot create the state directory '" + state_dir + "': " + ec.message());
  }
  const auto corner_path = (std::filesystem::path(state_dir) / "sim-corner.pbtxt").string();
  const auto floor_path = (std::filesystem::path(state_dir) / "sim-floor.pbtxt").string();
  if (!std::filesystem::exists(corner_path)) {
    CameraCalibration corner;
    corner.intrinsics = SimIntrinsics(1280, 1024);
    corner.ceiling_distance_m = kSimCeilingDistanceM;
    if (auto s = SaveCalibrationFileAtomically(corner_path, corner); !s) return s;
  }
  if (!std::filesystem::exists(floor_path)) {
    CameraCalibration floor;
    floor.intrinsics = SimIntrinsics(1280, 1024);
    floor.floor = FloorCalibration{};
    floor.floor->pose = SimFloorPose();
    if (auto s = SaveCalibrationFileAtomically(floor_path, floor); !s) return s;
  }
  return Ok{};
}

}  // namespace monocle
