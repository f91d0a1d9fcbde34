// The service's results as monocle's values (idl/protocol/values.h), which the protocol layer puts
// on the wire: one place where a processed frame becomes a Pose, a worker's figures a
// CameraStatus, a calibration file a Calibration.
#pragma once

#include <string>

#include "idl/protocol/values.h"
#include "service/io/calibration_file.h"
#include "service/server/camera_worker.h"
#include "service/server/service_config.h"

namespace monocle {

// The camera layer's state as the wire says it.
CameraState ToWire(SourceState state);
Pose PoseOf(const CameraSetup& camera, const ProcessedFrame& frame);
// `service_id`: this monocled, host/pid.
CameraStatus CameraStatusOf(const CameraSetup& camera, const WorkerStatus& status,
                            const std::string& service_id, int64_t stamp_ns);
Calibration CalibrationOf(const CameraSetup& camera, const CameraCalibration& calibration,
                          uint64_t revision, int64_t updated_ns);
FloorPoseEstimate FloorPoseOf(const FloorCalibration& floor);

}  // namespace monocle
