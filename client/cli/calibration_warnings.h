// Saying, once on stderr, that a calibration without the covariance of its intrinsics makes
// every 1 sigma printed too small by their share.
#pragma once

#include <string>

#include "monocle/client.h"
#include "service/io/calibration_file.h"

namespace monocle::cli {

// True (and a warning on stderr naming `path`) when `c` has no intrinsics covariance.
bool WarnIfIntrinsicsHaveNoCovariance(const std::string& path, const CameraCalibration& c);

// The same of the calibration the service uses for `camera` (its published file text).
bool WarnIfLiveIntrinsicsHaveNoCovariance(Client& client, const std::string& camera);

}  // namespace monocle::cli
