// A robot driving under a ceiling corner: a smooth, endless loop at a constant speed, its
// camera kept roughly on the corner while the robot also turns on its own (a sway of its
// heading), pitches and rolls a little. The pose at any time, so a simulated camera can play
// it forever and a renderer can blur a frame over its exposure.
#pragma once

#include <numbers>

#include "service/geometry/corner_pose.h"

namespace monocle {

struct DrivingPath {
  double speed_mps = 0.6;               // along the loop, constant
  double turn_deg_per_s = 20;           // peak rate of the robot's own turning (its heading's sway)
  double ceiling_distance_m = 1.6;      // camera to ceiling
  double loop_radius_m = 0.5;           // the loop is a circle ...
  double loop_centre_distance_m = 2.6;  // ... this far from the corner, horizontally
  double loop_bearing_rad = std::numbers::pi / 4;  // its centre's direction in the corner frame
  double sway_period_s = 2.0;                      // of the heading's sway
  double pitch_period_s = 1.3;                     // of the 1 degree pitch
  double roll_period_s = 0.9;                      // of the 0.5 degree roll
  double start_s = 0;                              // where on the loop time 0 is
};

// A path that comes back to where it started, as it was, every `lap_s` seconds: the loop, the
// sway, the pitch and the roll all repeat in that time (for a camera that plays a lap forever).
DrivingPath ClosedDrivingPath(double speed_mps, double turn_deg_per_s, double lap_s);

// The camera's pose at time `t_s` (seconds): position on the loop, pan aimed at the corner plus
// the sway, tilt aimed at the corner plus a 1 degree pitch, swing a 0.5 degree roll.
CornerPose DrivingPoseAt(const DrivingPath& path, double t_s);

// The largest rate of pan change over [t0_s, t1_s], sampled every dt_s (rad/s): the turn rate
// a sequence cut from the path actually shows, for reports.
double PeakPanRateRadPerS(const DrivingPath& path, double t0_s, double t1_s, double dt_s);

}  // namespace monocle
