// Renders what an upward-looking robot camera sees of a ceiling corner: the ceiling and two
// walls meeting in a "Y". Three looks: clean (each surface its own flat grey), cluttered
// (uneven lighting, texture and clutter: a lamp, a door frame, a ceiling fixture, a picture,
// a cable), and realistic (a white-painted room as cameras photograph it: surfaces 8-40
// grey levels apart, shading gradients, a lamp hot-spot, vignetting, defocus, sensor noise
// and JPEG). Used by tests, benchmarks and the simulated ceiling camera.
//
// Rays come from camera/render/reference_camera (OpenCV's undistortion and the paper's
// eq. (1) multiplied out), not from the code the locator solves with.
//
// Scene in the corner frame of service/geometry/corner_pose.h: ceiling z = 0, walls x = 0
// and y = 0, room x, y, z > 0 (z down from the ceiling).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <ostream>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"

namespace monocle {

// How a white-painted room photographs. Greys are before lighting; lighting multiplies.
struct RealisticLook {
  double ceiling_grey = 190;
  double wall_x0_grey = 170;  // the wall x = 0 (holds the Y and Z edges)
  double wall_y0_grey = 160;  // the wall y = 0 (holds the X and Z edges)
  // Shading across each surface: relative change per metre along its two in-plane axes
  // (ceiling: x, y; wall x = 0: y, z; wall y = 0: x, z).
  // (Eigen's default constructor leaves a vector uninitialised, hence the explicit zeros.)
  std::array<Eigen::Vector2d, 3> shading_per_m{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                                               Eigen::Vector2d::Zero()};
  double vignetting = 0.2;  // fraction darker at the image's corners (cos^4-like falloff)
  Eigen::Vector2d hotspot_px = Eigen::Vector2d(640, 300);  // a broad lamp glare
  double hotspot_radius_px = 350;                          // its Gaussian sigma
  double hotspot_gain = 0.15;                              // relative brightening at its centre
  double blur_sigma_px = 1.0;                              // defocus, Gaussian
  double noise_sigma = 3;                                  // sensor noise, grey levels
  int jpeg_quality = 80;                                   // 0: not compressed
};

std::ostream& operator<<(std::ostream& os, const RealisticLook& look);

// A random look within what white rooms show: ceiling-wall contrast 10-40 grey levels, the
// wall-wall edge 8-30, vignetting up to 30 %, a hot-spot anywhere, blur sigma 0.7-1.6 px,
// noise sigma 2-4, JPEG quality 70-90.
RealisticLook RandomRealisticLook(uint64_t seed, const CameraIntrinsics& intrinsics);

struct CornerScene {
  double room_size_m = 8.0;      // walls run this far from the corner
  double room_height_m = 2.8;    // ceiling to floor
  bool uneven_lighting = false;  // a lamp's falloff and a texture over every surface
  bool clutter = false;          // lamp, door frame, ceiling fixture, picture
  double noise_sigma = 0;        // Gaussian noise, grey levels
  uint64_t seed = 1;
  // Set: render the realistic look (its noise replaces noise_sigma).
  std::optional<RealisticLook> realistic;
  // Set: the camera moves from the rendered pose to this one while the shutter is open
  // (motion blur): the light is averaged over `motion_samples` poses evenly between them.
  std::optional<CornerPose> exposure_end_pose;
  int motion_samples = 4;
};

// 8-bit grey image of intrinsics.width_px x intrinsics.height_px. Pixels where materials
// meet are supersampled 4x4 so edges sit at their true subpixel place.
cv::Mat RenderCornerScene(const CameraIntrinsics& intrinsics, const CornerPose& pose,
                          const CornerScene& scene);

// The realistic look's light on the sensor (CV_32F grey levels): what RenderCornerScene
// returns before noise, rounding to 8 bits and JPEG. Needs scene.realistic.
cv::Mat RenderCornerExposure(const CameraIntrinsics& intrinsics, const CornerPose& pose,
                             const CornerScene& scene);

}  // namespace monocle
