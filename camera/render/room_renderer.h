// Renders what the robot's camera sees inside a room of a map (service/geometry/room_map.h):
// the ceiling, every wall of the room's outline and the floor, so several ceiling corners come
// into and out of view as the robot drives. Clean (flat greys) or the realistic look of
// corner_renderer.h (white paint 8-40 grey levels apart, shading, hot-spot, vignetting,
// defocus, noise, JPEG). Used by `monocle render room` and the room accuracy test.
//
// Rays from camera/render/reference_camera (OpenCV's undistortion), rotated by the camera's
// orientation in the map as the caller built it (not by the corner-frame code the locator
// solves with). Map frame: x, y on the floor, z up.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>

#include "camera/render/corner_renderer.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/room_map.h"

namespace monocle {

struct RoomScene {
  std::optional<RealisticLook> realistic;  // unset: clean greys
  uint64_t seed = 1;                       // noise
};

// `map_from_camera`: the optical frame (x right, y down, z forward) in the map; the camera
// must stand inside `room`. 8-bit grey, intrinsics.width_px x height_px; pixels where
// surfaces meet are supersampled 4x4.
cv::Mat RenderRoomView(const CameraIntrinsics& intrinsics, const MapRoom& room,
                       const Eigen::Isometry3d& map_from_camera, const RoomScene& scene);

}  // namespace monocle
