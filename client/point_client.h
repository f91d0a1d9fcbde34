// Client side of the service's point queries over DDS.
#pragma once

#include <string>
#include <vector>

#include "service/server/point_queries.h"

namespace monocle::client {

// Sends one point query to the running service (monocled) for floor camera `camera` and
// waits for its reply: the points in order, each measured or with its typed error; or the
// request's own typed error; or kNotFound when no service answers within `timeout_s`.
Result<RequestAnswer> MeasurePoints(const std::string& camera, const std::vector<PixelPair>& points,
                                    double pixel_sigma_px, int domain, double timeout_s);

}  // namespace monocle::client
