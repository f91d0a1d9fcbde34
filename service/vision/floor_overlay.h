// The picture of a floor calibration over the image it was made from: what a person
// checks at a glance (the corners found, the board as the result places it, the horizon,
// the robot frame's axes and distances on the floor).
#pragma once

#include <opencv2/core.hpp>

#include "service/geometry/floor_guidance.h"

namespace monocle {

// Draws into `image` (colour) what a floor pose means in the picture: lines of constant
// distance ahead on the floor (yellow, labelled in metres), the horizon (orange) and the robot
// frame's X_w and Y_w axes (red, magenta). Returns whether the horizon is in view.
bool DrawFloorFrame(cv::Mat& image, const CameraIntrinsics& k, const FloorPose& pose);

// A colour picture: `grey` with the detected corners (green), the board's squares reprojected
// through the calibrated pose (blue), the horizon (orange), the robot frame's X_w and Y_w
// axes (red, magenta) and lines of constant distance ahead on the floor (yellow, labelled in
// metres), and a caption with the result.
cv::Mat DrawFloorOverlay(const cv::Mat& grey, const CameraIntrinsics& k,
                         const FloorCalibration& floor, const BoardObservation& board,
                         const FloorGuidance& guidance);

}  // namespace monocle
