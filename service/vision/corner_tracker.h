// Corner pose over an ordered stream of frames: the three edges are predicted in the next
// frame from the motion so far (corner_motion.h) and measured there first, each searched
// within a gate as wide as the prediction is uncertain (a few hundred profiles instead of a
// Hough transform of the whole image); a full detection runs when tracking fails, when the
// tracked pose is suspect, and every N frames.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/corner_motion.h"
#include "service/vision/corner_locator.h"

namespace monocle {

// Pixels along the image of corner axis `axis` (0 X, 1 Y, 2 Z) as `pose` predicts it through
// the lens, from 8 px off the corner (where the edges separate) to the image border, every
// `spacing_px` of arc length. What tracking measures, and what overlays draw.
std::vector<Eigen::Vector2d> PredictEdgePx(const CameraIntrinsics& k, const CornerPose& pose,
                                           int axis, int spacing_px);

struct CornerTrackerOptions {
  int detect_every_n_frames = 30;  // a full detection at least this often (1: always detect)
  // Each edge is searched within +-3 sigma of its predicted place (the motion model's
  // uncertainty, in pixels across the edge), but at least and at most this far, pixels.
  double search_half_width_px = 6;
  double max_search_half_width_px = 60;
  // The search's points, pixels apart along each predicted edge: they only place the line
  // the locator measures again, every measure_spacing_px (CornerDetectorOptions).
  int spacing_px = 8;
  int measure_spacing_px = 6;
  double min_coverage = 0.25;  // each edge found on at least this much of its prediction
  CornerMotionOptions motion;
};

// How far each edge may be from where `prediction` puts it, pixels across the edge (1 sigma,
// the largest along its visible part): the pose's uncertainty carried through the lens.
std::array<double, 3> EdgeSigmaPx(const CameraIntrinsics& k, const CornerPrediction& prediction);

// The kinds of reason a suspect pose names (CornerLocation::suspect_reason, "; " between
// them): each reason up to its first ':' or figure, e.g. "the edges' steps do not add up".
std::set<std::string> SuspectReasonKinds(const std::string& reason);

class CornerTracker {
 public:
  CornerTracker(const CameraIntrinsics& intrinsics, double ceiling_distance_m,
                const CornerTrackerOptions& options = {},
                const CornerDetectorOptions& detector = {},
                const CornerQualityOptions& quality = {});

  // The pose in this frame; `source` says whether it was tracked or detected. `capture_time_s`
  // (any clock, seconds) paces the motion model; without it frames are taken as 1/30 s apart.
  Result<CornerLocation> Process(const cv::Mat& grey,
                                 std::optional<double> capture_time_s = std::nullopt);

  // Why the last frame that could have been tracked was detected instead (empty: it was not).
  const std::string& fallback_reason() const { return fallback_reason_; }

  // Forget the last pose (the next frame is detected), e.g. after a gap in the stream.
  void Reset();

 private:
  Result<CornerLocation> Track(const cv::Mat& grey, const CornerPrediction& prediction) const;

  CameraIntrinsics intrinsics_;
  double ceiling_distance_m_;
  CornerTrackerOptions options_;
  CornerDetectorOptions detector_;
  CornerQualityOptions quality_;
  CornerMotionModel motion_;
  double time_s_ = 0;  // of the frame being processed
  bool have_pose_ = false;
  // From the last detection (CornerEdges' two): noise changes slowly.
  double noise_sigma_grey_ = 0, measurement_noise_grey_ = 0;
  int frames_since_detection_ = 0;
  std::string fallback_reason_;
  // What the detection that started this track was suspect for (empty: it was not). A
  // tracked pose suspect for nothing else is kept, flagged, instead of detecting again.
  std::set<std::string> detection_suspect_kinds_;
};

}  // namespace monocle
