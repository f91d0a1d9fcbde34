// Renders what an upward-looking robot camera sees of a ceiling corner: the ceiling and two
// walls meeting in a "Y", each surface lit differently, with optional uneven lighting,
// texture and clutter (a lamp, a door frame, a ceiling fixture, a picture). Used by tests
// and the simulated ceiling camera.
//
// Scene in the corner frame of service/geometry/corner_pose.h: ceiling z = 0, walls x = 0
// and y = 0, room x, y, z > 0 (z down from the ceiling).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"

namespace monocle {

struct CornerScene {
  double room_size_m = 8.0;      // walls run this far from the corner
  double room_height_m = 2.8;    // ceiling to floor
  bool uneven_lighting = false;  // a lamp's falloff and a texture over every surface
  bool clutter = false;          // lamp, door frame, ceiling fixture, picture
  double noise_sigma = 0;        // Gaussian noise, grey levels
  uint64_t seed = 1;
};

// 8-bit grey image of intrinsics.width_px x intrinsics.height_px. Pixels where materials
// meet are supersampled 4x4 so edges sit at their true subpixel place.
cv::Mat RenderCornerScene(const CameraIntrinsics& intrinsics, const CornerPose& pose,
                          const CornerScene& scene);

}  // namespace monocle
