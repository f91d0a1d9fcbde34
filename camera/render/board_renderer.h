// Renders a chessboard held anywhere in front of a camera, as the views of an intrinsic
// calibration, with ground truth: the board pose of every view is known.
//
// Board frame: origin at inner corner (0, 0), x along the `cols` inner corners, y along the
// `rows`, z = x cross y; metres. The printed pattern reaches one square beyond the inner
// corners with a white margin of one more square, as real calibration targets do.
// Anti-aliasing is analytic (each pixel averages the pattern over its footprint on the
// board), so inner corners land at their true subpixel place before blur and noise.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "camera/render/photograph.h"
#include "service/geometry/camera_model.h"

namespace monocle {

struct CheckerPattern {
  int cols = 9;  // inner corners along x
  int rows = 6;  // inner corners along y
  double square_m = 0.05;
  double white = 225, black = 25;  // grey levels of the printed squares
};

// Grey level of the pattern averaged over the box [x - wx, x + wx] x [y - wy, y + wy]
// (board metres), blended into `surround` outside the board's margin.
double CheckerValue(const CheckerPattern& pattern, double x, double y, double wx, double wy,
                    double surround);

struct BoardViewPose {
  Eigen::Matrix3d r_camera_board = Eigen::Matrix3d::Identity();  // board -> camera
  Eigen::Vector3d t_camera_board_m = Eigen::Vector3d(0, 0, 1);
};

// How the view photographs: uneven light across the board (a gradient), vignetting, blur,
// noise, JPEG.
struct BoardLook {
  double background = 120;                                          // grey level around the board
  Eigen::Vector2d light_gradient_per_px = Eigen::Vector2d::Zero();  // relative, across the image
  PhotoEffects effects;
};

// Within what a hand-held board under room light shows: contrast 120-200 grey levels, light
// varying by up to +-25 % across the image, vignetting up to 30 %, blur sigma 0.5-1.2 px,
// noise sigma 1-3, JPEG quality 80-95.
BoardLook RandomBoardLook(uint64_t seed, const CameraIntrinsics& k, CheckerPattern* pattern);

cv::Mat RenderBoardView(const CameraIntrinsics& k, const BoardViewPose& pose,
                        const CheckerPattern& pattern, const BoardLook& look, uint64_t seed);

// Pixels of the inner corners (index j * cols + i) by cv::projectPoints: the ground truth.
std::vector<Eigen::Vector2d> ProjectBoardCorners(const CameraIntrinsics& k,
                                                 const BoardViewPose& pose,
                                                 const CheckerPattern& pattern);

enum class ViewSpread {
  kGood,            // near every corner and edge of the image, tilted 15-40 degrees
  kFrontoParallel,  // facing the camera (tilt < 3 degrees), anywhere in the image
  kOneCorner,       // tilted, but always in the image's top-left quarter
};

// `count` random views of the whole board (with its margin) inside the image.
std::vector<BoardViewPose> RandomBoardViews(const CameraIntrinsics& k,
                                            const CheckerPattern& pattern, int count, uint64_t seed,
                                            ViewSpread spread);

}  // namespace monocle
