#include "service/vision/corner_level.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "service/geometry/mount_level.h"

namespace monocle {
namespace {

// `value` with `decimals` digits after the point, as the messages print it.
std::string Fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

double Degrees(double rad) { return rad * 180 / std::numbers::pi; }

}  // namespace

void ApplyMountLevel(const RigidTransform& base_camera, const MountLevelOptions& options,
                     const CornerQualityOptions& quality, CornerLocation* location) {
  const LevelledCornerPose levelled =
      LevelWithMount(location->pose, location->covariance, base_camera, options.level_sigma_rad);
  location->level_error_rad = levelled.level_error_rad;
  location->level_sigma_rad = options.level_sigma_rad;
  if (levelled.level_error_rad > options.max_level_error_rad &&
      levelled.tip_mahalanobis2 > options.max_tip_mahalanobis2) {
    // The image and the mount disagree (a wrong Y, a wrong mount, a ramp): the pose stays as
    // the image gave it, flagged; combining the two would make a pose neither supports.
    const std::string reason =
        "the pose tips the robot " + Fixed(Degrees(levelled.level_error_rad), 2) +
        " deg from level (allowed " + Fixed(Degrees(options.max_level_error_rad), 2) + " deg; " +
        Fixed(std::sqrt(levelled.tip_mahalanobis2), 1) +
        " sigma of the pose's own and the level's)";
    location->suspect_reason += (location->suspect ? "; " : "") + reason;
    location->suspect = true;
    location->suspect_only_imprecise = false;
    return;
  }
  location->pose = levelled.pose;
  location->covariance = levelled.covariance;
  location->q_corner_camera =
      Eigen::Quaterniond(RotationCameraFromCorner(levelled.pose).transpose()).normalized();
  // The 1 sigma has changed: the imprecision among the pose's reasons (if any) is judged and
  // stated again; the others (its edges) stand.
  std::vector<std::string> reasons;
  for (size_t begin = 0; begin < location->suspect_reason.size();) {
    size_t end = location->suspect_reason.find("; ", begin);
    if (end == std::string::npos) end = location->suspect_reason.size();
    std::string reason = location->suspect_reason.substr(begin, end - begin);
    if (!reason.empty() && !IsImprecisionReason(reason)) reasons.push_back(std::move(reason));
    begin = end + 2;
  }
  const bool others = !reasons.empty();
  if (auto imprecise = ImprecisionReason(location->pose, location->covariance, quality,
                                         "with the mount's level");
      !imprecise.empty()) {
    reasons.push_back(std::move(imprecise));
  }
  location->suspect = !reasons.empty();
  location->suspect_only_imprecise = location->suspect && !others;
  location->suspect_reason.clear();
  for (const auto& r : reasons)
    location->suspect_reason += (location->suspect_reason.empty() ? "" : "; ") + r;
}

}  // namespace monocle
