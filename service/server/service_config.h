// monocled's configuration: the text-protobuf file (idl/service_config.proto) turned into
// validated values once, at the boundary. Errors name the file, the line and the field.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "camera/aravis/aravis_source.h"
#include "service/common/result.h"

namespace monocle {

enum class CameraRole { kCorner, kFloor, kCornerAndFloor };

const char* ToString(CameraRole role);  // "corner", "floor", "corner+floor"

struct CameraSetup {
  std::string id;         // name on DDS and in requests
  AravisOptions options;  // device and GenICam settings
  CameraRole role = CameraRole::kCorner;
  std::string calibration_path;              // resolved against the config's directory
  std::optional<double> ceiling_distance_m;  // overrides the calibration file's
  std::chrono::milliseconds stall_timeout{1000};

  bool corner() const { return role != CameraRole::kFloor; }
  bool floor() const { return role != CameraRole::kCorner; }
};

struct ServiceSetup {
  int domain = 0;
  std::vector<CameraSetup> cameras;
  std::chrono::milliseconds status_period{1000};
};

// `source` names the file in messages; relative calibration paths resolve against `base_dir`.
Result<ServiceSetup> ParseServiceConfig(const std::string& text, const std::string& source,
                                        const std::string& base_dir);
Result<ServiceSetup> LoadServiceConfig(const std::string& path);

// The configuration used when monocled is given none: the in-process simulated cameras
// sim-corner and sim-floor, with calibration files in `state_dir` (see
// EnsureSimulatorCalibrations).
std::string EmbeddedDefaultConfig();

// Writes the simulated cameras' calibration files (sim-corner.pbtxt, sim-floor.pbtxt) into
// `state_dir` unless they exist already (a floor calibration command may have updated them).
Status EnsureSimulatorCalibrations(const std::string& state_dir);

}  // namespace monocle
