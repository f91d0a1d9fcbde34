// Answers point queries: pixels of a floor camera -> robot-frame points with 1-sigma.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "service/common/point_query.h"
#include "service/geometry/floor_model.h"
#include "service/io/calibration_file.h"

namespace monocle {

// Points in one request: a larger one is refused with a typed error (the wire's sample limit,
// idl/protocol/wire.h, is sized to carry this many).
inline constexpr size_t kMaxPointsPerRequest = 100000;
inline constexpr double kDefaultPixelSigmaPx = 0.5;

enum class RequestStatus : uint8_t { kAnswered = 0, kInvalidRequest = 1 };

struct RequestAnswer {
  RequestStatus status = RequestStatus::kAnswered;
  std::string error;
  std::vector<MeasuredPoint> points;  // one per pixel, in order
};

// `cameras`: calibration of every floor camera by id. Never throws; every malformed input
// is a typed status with a message.
RequestAnswer AnswerPointRequest(const std::map<std::string, CameraCalibration>& cameras,
                                 const std::string& camera_id,
                                 const std::vector<PixelQuery>& points, double pixel_sigma_px);

// A floor-model measurement as the answer to one pixel.
MeasuredPoint ToMeasuredPoint(const FloorMeasurement& measurement);

}  // namespace monocle
