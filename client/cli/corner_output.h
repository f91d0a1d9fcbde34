// How `monocle corner locate` and `monocle replay` show a corner pose: one text line, the JSON
// object (idl/cli_output.proto CornerOutput), and the overlay picture.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>

#include "idl/cli_output.pb.h"
#include "service/common/result.h"
#include "service/vision/corner_locator.h"

namespace monocle::cli {

extern const char* kAxisName[3];  // "X", "Y", "Z": the corner frame's axes, edge by edge

// `label  x=... y=... z=... m  pan=... rad  (1σ ...)  corner u,v px  rms ... px  detected`
std::string CornerResultLine(const std::string& label, const CornerLocation& result);

proto::CornerOutput ToCornerOutput(const std::string& image, const Result<CornerLocation>& r);

// The robot base in the corner frame, as the JSON shows it: from its position (metres),
// orientation (w, x, y, z), heading (rad) and the covariance of (x, y, heading).
proto::BasePoseOutput ToBaseOutput(const std::array<double, 3>& position_m,
                                   const std::array<double, 4>& quaternion_wxyz, double heading_rad,
                                   const std::array<double, 9>& covariance);
// "  base x=... y=... m heading=... deg  (1σ x y m, heading deg)", as pose lines end.
std::string BaseText(const proto::BasePoseOutput& base);

// The image in colour with what the locator saw and concluded: the straight segments the
// detector found, the three edges as far as they were measured, the edges the chosen pose
// predicts (through the lens, to the border), each edge's support (length, coverage,
// contrast against the noise, misfit to the pose), the pose, and SUSPECT with its reason.
cv::Mat DrawCornerOverlay(const cv::Mat& grey, const CameraIntrinsics& intrinsics,
                          const Result<CornerLocation>& result);

// DIR/<image stem>.overlay.png: DrawCornerOverlay's picture.
void WriteCornerOverlay(const std::string& dir, const std::string& image_path, const cv::Mat& grey,
                        const CameraIntrinsics& intrinsics, const Result<CornerLocation>& result);

}  // namespace monocle::cli
