// Seeded random cameras and poses shared by the geometry tests and benchmarks.
#pragma once

#include <numbers>
#include <random>

#include "service/geometry/camera_model.h"
#include "service/geometry/floor_model.h"

namespace monocle::testing {

// The camera of Xu et al. 2017, section 5.1 (1280x1024, Daheng MER-130-30UC).
inline CameraIntrinsics PaperCamera() {
  CameraIntrinsics k;
  k.width_px = 1280;
  k.height_px = 1024;
  k.fx = 1624.33959;
  k.fy = 1623.03660;
  k.cx = 634.76907;
  k.cy = 499.01788;
  k.distortion = {-0.07021, 0.07348, -0.00112, 0.00267, 0, 0, 0, 0};
  return k;
}

// The paper camera behind a strong wide-angle lens (radial to k3, tangential).
inline CameraIntrinsics WideAnglePaperCamera() {
  CameraIntrinsics k = PaperCamera();
  k.distortion = {-0.28, 0.09, 0.0007, -0.0004, -0.012, 0, 0, 0};
  return k;
}

// A 640x512 industrial camera with a mild wide-angle lens (radial and tangential
// distortion): small enough for tests that calibrate it many times.
inline CameraIntrinsics SmallWideAngleCamera() {
  CameraIntrinsics k;
  k.width_px = 640;
  k.height_px = 512;
  k.fx = 560.3;
  k.fy = 559.1;
  k.cx = 322.6;
  k.cy = 249.4;
  k.distortion = {-0.21, 0.08, 0.0009, -0.0012, 0, 0, 0, 0};
  return k;
}

inline double Deg(double d) { return d * std::numbers::pi / 180.0; }

// Random floor pose in the range a robot camera looks at the floor from.
inline FloorPose RandomFloorPose(std::mt19937_64& rng, bool with_roll = true) {
  std::uniform_real_distribution<double> height(0.3, 2.5), pitch(Deg(95), Deg(150)),
      yaw(Deg(-20), Deg(20)), roll(Deg(-10), Deg(10));
  return FloorPose{height(rng), pitch(rng), yaw(rng), with_roll ? roll(rng) : 0.0};
}

}  // namespace monocle::testing
