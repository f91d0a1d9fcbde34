// `monocled --replay FILE.mcap`: the service's cameras made from a recording. Every camera
// with frames in the file is served under its recorded id and ROS namespace, with the
// calibration the recording started with and the role it had, so clients see what they saw
// on the robot.
#pragma once

#include <string>

#include "service/common/result.h"
#include "service/server/service_config.h"

namespace monocle {

// Copies each camera's recorded calibration to `state_dir`/replay/<id>.pbtxt (floor
// calibration commands during the replay change that copy, never a file of the robot's),
// and validates everything as a configuration file would be.
Result<ServiceSetup> ReplaySetup(const std::string& mcap_path, const std::string& state_dir,
                                 ReplayPace pace);

}  // namespace monocle
