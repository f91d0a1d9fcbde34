// Calibration files: text-format protobuf (idl/calibration.proto), validated on load and
// written atomically.
#pragma once

#include <optional>
#include <string>

#include "idl/calibration.pb.h"
#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/floor_calibration.h"
#include "service/io/atomic_file.h"  // WriteFileAtomically, for every text file

namespace monocle {

struct CameraCalibration {
  CameraIntrinsics intrinsics;
  std::optional<FloorCalibration> floor;       // absent until the floor is calibrated
  std::optional<double> ceiling_distance_m;    // corner { ceiling_distance }
  std::optional<double> corner_max_swing_rad;  // corner { max_swing }
  double intrinsics_rms_px = 0;                // 0 when unknown
  // Zero when unknown (a file written by hand or before monocle tracked it).
  IntrinsicsCovariance intrinsics_covariance = IntrinsicsCovariance::Zero();
  std::string distortion_model;  // "k1k2", "k1k2p1p2", "k1k2p1p2k3"; empty when unknown
};

// Whether the calibration has intrinsics (an image topic's camera may wait for camera_info's).
inline bool HasIntrinsics(const CameraCalibration& calibration) {
  return calibration.intrinsics.width_px > 0 && calibration.intrinsics.fx > 0;
}

// Parses text-format protobuf. Errors name the line and column (syntax, unknown fields)
// or the field (missing or impossible values). `source` names the file in messages.
Result<CameraCalibration> ParseCalibration(const std::string& text, const std::string& source);

Result<CameraCalibration> LoadCalibrationFile(const std::string& path);

std::string FormatCalibration(const CameraCalibration& calibration);

// Replaces `path` whole (atomic_file.h): readers see either the old or the new file, never a
// partial one, and a write that was killed leaves no temporary behind for good.
Status SaveCalibrationFileAtomically(const std::string& path, const CameraCalibration& calibration);

}  // namespace monocle
