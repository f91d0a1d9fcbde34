// Conversions between the corner pose and its DDS sample.
#pragma once

#include <string>

#include "idl/monocle.h"
#include "service/vision/corner_locator.h"

namespace monocle::dds {

// Fills `out` (its string fields point into `camera_id`, `error` and `pose`, which must outlive
// it).
void ToSample(const std::string& camera_id, uint64_t sequence, int64_t capture_time_ns,
              bool camera_clock, const Result<CornerLocation>& pose, int64_t processing_ns,
              monocle_dds_CornerPose* out, std::string* error);

}  // namespace monocle::dds
