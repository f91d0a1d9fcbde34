// Renders what a floor camera sees: a chessboard lying on the floor, optional boxes standing
// on it, and a wall beyond the horizon. Used by tests now and the simulated floor camera.
//
// Anti-aliasing is analytic: each pixel integrates the checker pattern over its footprint
// on the floor (a box in board coordinates), so corners land at their true subpixel place.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "service/geometry/camera_model.h"
#include "service/geometry/floor_model.h"

namespace monocle {

// An axis-aligned box standing on the floor, robot frame, metres.
struct FloorBox {
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d size_m = Eigen::Vector2d(0.3, 0.3);  // along X_w, Y_w
  double height_m = 0.3;
};

struct FloorScene {
  int board_cols = 9;  // inner corners along x_p
  int board_rows = 6;  // inner corners along y_p
  double square_m = 0.1;
  Eigen::Vector2d board_origin_robot_m = Eigen::Vector2d(0, 2);  // inner corner (0, 0)
  std::vector<FloorBox> boxes;
  double noise_sigma = 0;  // Gaussian noise, grey levels
  uint64_t seed = 1;
};

// Board origin that centres the board on the point where the optical axis meets the
// floor (or 2 m ahead if it never does).
Eigen::Vector2d CenteredBoardOrigin(const FloorPose& pose, int cols, int rows, double square_m);

// 8-bit grey image of intrinsics.width_px x intrinsics.height_px.
cv::Mat RenderFloorScene(const CameraIntrinsics& intrinsics, const FloorPose& pose,
                         const FloorScene& scene);

}  // namespace monocle
