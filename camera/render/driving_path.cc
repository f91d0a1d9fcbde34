#include "camera/render/driving_path.h"

#include <algorithm>
#include <cmath>

namespace monocle {

CornerPose DrivingPoseAt(const DrivingPath& path, double t_s) {
  using std::numbers::pi;
  const double t = t_s + path.start_s;
  const double loop_angle = path.speed_mps * t / path.loop_radius_m;
  const double x = path.loop_centre_distance_m * std::cos(path.loop_bearing_rad) +
                   path.loop_radius_m * std::cos(loop_angle);
  const double y = path.loop_centre_distance_m * std::sin(path.loop_bearing_rad) +
                   path.loop_radius_m * std::sin(loop_angle);
  // A sinusoidal sway whose peak rate is turn_deg_per_s: amplitude = rate / angular frequency.
  const double sway_w = 2 * pi / path.sway_period_s;
  const double sway_rad = path.turn_deg_per_s * pi / 180 / sway_w * std::sin(sway_w * t);
  CornerPose pose;
  pose.x_m = x;
  pose.y_m = y;
  pose.z_m = path.ceiling_distance_m;
  // pan atan2(x, -y) and tilt atan2(horizontal distance, z) put the corner on the optical axis.
  pose.pan_rad = std::atan2(x, -y) + sway_rad;
  pose.tilt_rad = std::atan2(std::hypot(x, y), path.ceiling_distance_m) +
                  pi / 180 * std::sin(2 * pi * t / path.pitch_period_s);
  pose.swing_rad = 0.5 * pi / 180 * std::sin(2 * pi * t / path.roll_period_s + 1);
  return pose;
}

DrivingPath ClosedDrivingPath(double speed_mps, double turn_deg_per_s, double lap_s) {
  DrivingPath path;
  path.speed_mps = speed_mps;
  path.turn_deg_per_s = turn_deg_per_s;
  path.loop_radius_m = std::max(speed_mps * lap_s / (2 * std::numbers::pi), 1e-6);
  // Whole numbers of sways, nods and rolls a lap, each about 2 s or less: a long sway at a
  // given turn rate would swing the corner out of view.
  const double cycles = std::max(1.0, std::round(lap_s / 2.0));
  path.sway_period_s = lap_s / cycles;
  path.pitch_period_s = lap_s / cycles;
  path.roll_period_s = lap_s / cycles;
  return path;
}

double PeakPanRateRadPerS(const DrivingPath& path, double t0_s, double t1_s, double dt_s) {
  double peak = 0;
  for (double t = t0_s; t + dt_s <= t1_s; t += dt_s) {
    const double rate =
        (DrivingPoseAt(path, t + dt_s).pan_rad - DrivingPoseAt(path, t).pan_rad) / dt_s;
    peak = std::max(peak, std::abs(rate));
  }
  return peak;
}

}  // namespace monocle
