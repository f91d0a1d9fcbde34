#include "service/geometry/corner_motion.h"

#include <cmath>
#include <numbers>

namespace monocle {
namespace {

double WrappedAngle(double a) { return std::remainder(a, 2 * std::numbers::pi); }

}  // namespace

PoseVector PoseDifference(const CornerPose& to, const CornerPose& from) {
  PoseVector d;
  d << to.x_m - from.x_m, to.y_m - from.y_m, WrappedAngle(to.pan_rad - from.pan_rad),
      WrappedAngle(to.tilt_rad - from.tilt_rad), WrappedAngle(to.swing_rad - from.swing_rad);
  return d;
}

std::optional<CornerPrediction> CornerMotionModel::Predict(double time_s) const {
  if (!last_pose_) return std::nullopt;
  const double dt = std::max(0.0, time_s - last_time_s_);
  CornerPrediction out;
  PoseVector floor_per_s;
  if (!velocity_) {
    out.pose = *last_pose_;
    floor_per_s << options_.static_m_per_s, options_.static_m_per_s, options_.static_rad_per_s,
        options_.static_rad_per_s, options_.static_rad_per_s;
    out.sigma = dt * floor_per_s;
    return out;
  }
  out.has_velocity = true;
  out.pose = MovedBy(*last_pose_, dt * *velocity_);
  floor_per_s << options_.floor_m_per_s, options_.floor_m_per_s, options_.floor_rad_per_s,
      options_.floor_rad_per_s, options_.floor_rad_per_s;
  // A miss grows with the time predicted over: the misses so far, scaled to this interval.
  out.sigma = dt * floor_per_s.cwiseMax(miss_rms_per_s_);
  return out;
}

void CornerMotionModel::Update(const CornerPose& pose, double time_s) {
  if (last_pose_ && time_s > last_time_s_) {
    const double dt = time_s - last_time_s_;
    if (velocity_) {
      const PoseVector predicted_change = dt * *velocity_;
      const PoseVector miss_per_s = (PoseDifference(pose, *last_pose_) - predicted_change) / dt;
      const PoseVector squared = miss_per_s.cwiseAbs2();
      const double w = have_misses_ ? options_.innovation_weight : 1.0;
      miss_rms_per_s_ = ((1 - w) * miss_rms_per_s_.cwiseAbs2() + w * squared).cwiseSqrt();
      have_misses_ = true;
    }
    velocity_ = PoseDifference(pose, *last_pose_) / dt;
  } else if (last_pose_) {
    velocity_.reset();  // time went backwards or stood still: start the velocity again
  }
  last_pose_ = pose;
  last_time_s_ = time_s;
}

void CornerMotionModel::Reset() {
  last_pose_.reset();
  velocity_.reset();
  miss_rms_per_s_.setZero();
  have_misses_ = false;
}

}  // namespace monocle
