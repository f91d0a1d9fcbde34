// How good a floor calibration is for the points a user wants to measure, and what to
// change when it is not good enough: the board too far, too small in the image, seen too
// obliquely; or a solve that carries no information at all. Pure geometry: the advice is
// predicted with the same first-order propagation the measurements use.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/common/floor_report.h"
#include "service/geometry/floor_calibration.h"

namespace monocle {

// A floor calibration's height scales with the board's square: a height no robot's camera has
// (outside 0.05-10 m) is most likely a square given in centimetres or millimetres. Says so,
// with the square and height each reading would give, naming the square and the override as
// the caller's user knows them; empty when the height is one a robot's camera may have.
struct UnitSlipWords {
  std::string square = "--square";
  std::string force = "--force";
};
std::optional<std::string> FloorHeightUnitSlip(double height_m, double square_m,
                                               const UnitSlipWords& words = {});

// `board` is what the calibration was fitted to; `pixel_sigma_px` the noise of a query
// pixel (as `monocle floor measure --pixel-sigma`).
FloorGuidance AdviseFloorCalibration(const CameraIntrinsics& k,
                                     const IntrinsicsCovariance& k_covariance,
                                     const FloorCalibration& floor, const BoardObservation& board,
                                     double pixel_sigma_px,
                                     const std::optional<FloorAccuracyTarget>& target);

}  // namespace monocle
