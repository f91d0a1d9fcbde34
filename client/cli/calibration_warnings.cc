#include "client/cli/calibration_warnings.h"

#include <iostream>

namespace monocle::cli {

// A calibration without the covariance of its intrinsics (imported from another tool, or
// written by hand) makes every 1 sigma too small by their share: say so, once, on stderr.
bool WarnIfIntrinsicsHaveNoCovariance(const std::string& path, const CameraCalibration& c) {
  if (!c.intrinsics_covariance.isZero()) return false;
  std::cerr << "monocle: warning: " << path
            << " has no covariance of its intrinsics (imported, typed in, or a simulator's): the 1 "
               "sigma below leaves the calibration's uncertainty out; monocle intrinsics "
               "calibrate measures it\n";
  return true;
}

// The same of the calibration the service uses for `camera` (its published file text).
bool WarnIfLiveIntrinsicsHaveNoCovariance(Client& client, const std::string& camera) {
  const auto published = client.calibrations();
  if (!published) return false;
  for (const auto& c : *published) {
    if (c.camera_id != camera) continue;
    const auto parsed = ParseCalibration(c.text, c.file);
    return parsed && WarnIfIntrinsicsHaveNoCovariance(c.file + " (camera " + camera + ")", *parsed);
  }
  return false;
}

}  // namespace monocle::cli
