// Answers point queries: pixels of a floor camera -> robot-frame points with 1-sigma.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "service/geometry/floor_model.h"
#include "service/io/calibration_file.h"

namespace monocle {

// Points in one request: a larger one is refused with a typed error (the wire's sample limit,
// idl/protocol/wire.h, is sized to carry this many).
inline constexpr size_t kMaxPointsPerRequest = 100000;
inline constexpr double kDefaultPixelSigmaPx = 0.5;

struct PixelPair {
  double u = 0, v = 0;
  bool paired = false;  // (u, v) stands vertically above (floor_u, floor_v)
  double floor_u = 0, floor_v = 0;
};

enum class PointStatus : uint8_t { kMeasured = 0, kInvalidPixel = 1, kNotMeasurable = 2 };
enum class RequestStatus : uint8_t { kAnswered = 0, kInvalidRequest = 1 };

struct PointAnswer {
  PointStatus status = PointStatus::kMeasured;
  FloorMeasurement measurement;
  std::string error;
};

struct RequestAnswer {
  RequestStatus status = RequestStatus::kAnswered;
  std::string error;
  std::vector<PointAnswer> points;
};

// `cameras`: calibration of every floor camera by id. Never throws; every malformed input
// is a typed status with a message.
RequestAnswer AnswerPointRequest(const std::map<std::string, CameraCalibration>& cameras,
                                 const std::string& camera_id, const std::vector<PixelPair>& points,
                                 double pixel_sigma_px);

}  // namespace monocle
