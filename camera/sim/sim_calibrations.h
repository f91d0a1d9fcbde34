// The built-in simulated cameras' calibration files, seeded where monocled keeps its state.
#pragma once

#include <string>

#include "service/common/result.h"

namespace monocle {

// Writes the simulated cameras' calibration files (sim-corner.pbtxt, sim-floor.pbtxt) into
// `state_dir` unless they exist already (a floor calibration command may have updated them).
Status EnsureSimulatorCalibrations(const std::string& state_dir);

}  // namespace monocle
