// Shared by the corner pose's tests: the camera they solve in and a pose comparison.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "service/geometry/corner_pose.h"
#include "service/geometry/test_scenes.h"

namespace monocle::testing {

// The paper camera without distortion, f = 1600 px, centred in 1280 x 1024.
inline CameraIntrinsics CornerCamera() {
  CameraIntrinsics k = testing::PaperCamera();
  k.fx = k.fy = 1600;
  k.cx = 640;
  k.cy = 512;
  k.distortion = {};
  return k;
}

// |a - b| modulo 2 pi, radians.
inline double AngleDiff(double a, double b) {
  return std::abs(std::remainder(a - b, 2 * std::numbers::pi));
}

// Position within `tol` (relative beyond 1 m), angles within `tol` rad.
inline void ExpectPoseNear(const CornerPose& got, const CornerPose& want, double tol) {
  EXPECT_NEAR(got.x_m, want.x_m, tol * std::max(1.0, want.x_m)) << got << " vs " << want;
  EXPECT_NEAR(got.y_m, want.y_m, tol * std::max(1.0, want.y_m)) << got << " vs " << want;
  EXPECT_NEAR(got.z_m, want.z_m, tol) << got << " vs " << want;
  EXPECT_LT(AngleDiff(got.pan_rad, want.pan_rad), tol) << got << " vs " << want;
  EXPECT_LT(AngleDiff(got.tilt_rad, want.tilt_rad), tol) << got << " vs " << want;
  EXPECT_LT(AngleDiff(got.swing_rad, want.swing_rad), tol) << got << " vs " << want;
}

}  // namespace monocle::testing
