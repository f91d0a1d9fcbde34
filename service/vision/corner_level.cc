#include "service/vision/corner_level.h"

#include <cmath>
#include <cstdio>
#include <string>

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
  if (location->suspect_only_imprecise) {
    // Its only reason was the 1 sigma, which the level has changed: judge it again.
    const double horizontal = std::hypot(location->pose.x_m, location->pose.y_m);
    const double sigma_h = std::sqrt(location->covariance(0, 0) + location->covariance(1, 1));
    location->suspect = sigma_h > quality.max_relative_sigma * horizontal;
    location->suspect_only_imprecise = location->suspect;
    location->suspect_reason =
        location->suspect ? "position uncertain: 1 sigma " + Fixed(100 * sigma_h / horizontal, 1) +
                                " % of the distance with the mount's level (more than " +
                                Fixed(100 * quality.max_relative_sigma, 1) + ")"
                          : "";
  }
}

}  // namespace monocle
