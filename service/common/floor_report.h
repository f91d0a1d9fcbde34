// How good a floor calibration is for the points a user wants to measure, one type from the
// geometry that works it out (floor_guidance.h) to the wire and the client: where the board
// lay, the 1 sigma of a floor point ahead, whether an accuracy target is met and what to
// change. Plain values, no Eigen: the client library installs this header as
// monocle/floor_report.h.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace monocle {

// "1 sigma of a floor point at most sigma_m, distance_m ahead of the camera".
struct FloorAccuracyTarget {
  double sigma_m = 0;       // larger horizontal axis of the point's 1 sigma, metres
  double distance_m = 3.0;  // along the floor straight ahead (robot frame Y_w), metres
};

// Where the board lay, as the camera saw it.
struct BoardPlacement {
  double distance_m = 0;       // optical centre to the board's centre, metres
  double depth_span_m = 0;     // the board's extent along Y_w (away from the camera), metres
  double image_fraction = 0;   // area of the board's outline / area of the image
  double sight_angle_deg = 0;  // line of sight to the board's centre, above the floor, degrees
};

// 1 sigma of the floor point (0, distance_m, 0), robot frame, and where it comes from:
// metres, along the point's least certain horizontal direction (mostly the line of sight),
// so that calibration^2 + pixel^2 = sigma^2.
struct FloorAccuracyAt {
  double distance_m = 0;
  bool in_image = false;           // the point is inside the image
  double sigma_m = 0;              // everything: calibration and the query pixel
  double calibration_sigma_m = 0;  // the calibration's share (board corners and intrinsics)
  double intrinsics_sigma_m = 0;   // of which the intrinsics'
  double pixel_sigma_m = 0;        // the query pixel's own noise
};

// A board placement the advice proposes: the same corners, squares of `square_m`, laid
// straight ahead with its centre `ground_distance_m` from the camera's foot, and the 1 sigma
// at the target's distance the full method would then give.
struct BoardSuggestion {
  double ground_distance_m = 0;
  double square_m = 0;
  double predicted_sigma_m = 0;
};

struct FloorGuidance {
  BoardPlacement board;
  std::vector<FloorAccuracyAt> accuracy;  // at 1, 2 and 4 m, and at the target's distance
  std::optional<FloorAccuracyTarget> target;
  bool target_met = true;
  double target_met_out_to_m = 0;  // the target's sigma holds out to here (0: nowhere)
  // The result says nothing useful (1 sigma of the height > 25 % of it, or of the pitch
  // > 0.1 rad); `ill_conditioned_reason` says why, in a user's words.
  bool ill_conditioned = false;
  std::string ill_conditioned_reason;
  std::vector<std::string> advice;           // what to change, each with its predicted effect
  std::vector<BoardSuggestion> suggestions;  // the placements the advice names
};

}  // namespace monocle
