// Where the camera will be in the next frame: a constant-velocity model of a corner pose over
// time, with how far off its predictions have been. The tracker searches for the edges within
// a gate this uncertainty sets, so a fast but smooth drive is followed and a jolt widens it.
// Pure geometry: Eigen only.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "service/geometry/corner_pose.h"

namespace monocle {

using PoseVector = Eigen::Matrix<double, 5, 1>;  // (x, y, pan, tilt, swing): m, m, rad, rad, rad

struct CornerPrediction {
  CornerPose pose;
  // 1 sigma of each of (x, y, pan, tilt, swing) about `pose`: metres and radians.
  PoseVector sigma = PoseVector::Zero();
  bool has_velocity = false;  // false: only one pose seen, the prediction is that pose
};

struct CornerMotionOptions {
  // What the prediction may be off by at least, per second of prediction, when everything
  // so far was smooth: 5 cm/s and 3 deg/s (a robot's tremor, a pose's own noise).
  double floor_m_per_s = 0.05;
  double floor_rad_per_s = 0.05;
  // With one pose only: how far the camera may have moved per second (1.5 m/s, 60 deg/s).
  double static_m_per_s = 1.5;
  double static_rad_per_s = 1.05;
  // How fast the memory of past misses fades (weight of the newest, 0..1).
  double innovation_weight = 0.3;
};

class CornerMotionModel {
 public:
  explicit CornerMotionModel(const CornerMotionOptions& options = {}) : options_(options) {}

  // The pose at `time_s`, from the poses given so far (nothing before the first).
  std::optional<CornerPrediction> Predict(double time_s) const;
  // A pose measured at `time_s` (later than the last one): updates the velocity and, when it
  // was predicted, the record of how far predictions miss.
  void Update(const CornerPose& pose, double time_s);
  void Reset();

 private:
  CornerMotionOptions options_;
  std::optional<CornerPose> last_pose_;
  double last_time_s_ = 0;
  std::optional<PoseVector> velocity_;              // per second
  PoseVector miss_rms_per_s_ = PoseVector::Zero();  // RMS prediction miss, per second predicted
  bool have_misses_ = false;
};

// `to` less `from` as (x, y, pan, tilt, swing), angles wrapped into (-pi, pi].
PoseVector PoseDifference(const CornerPose& to, const CornerPose& from);

}  // namespace monocle
