// Corner pose over an ordered stream of frames: the three edges are predicted in the next
// frame from the last pose and measured there first (a few hundred profiles instead of a
// Hough transform of the whole image); a full detection runs when tracking fails, when the
// tracked pose is suspect, and every N frames.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/vision/corner_locator.h"

namespace monocle {

// Pixels along the image of corner axis `axis` (0 X, 1 Y, 2 Z) as `pose` predicts it through
// the lens, from 8 px off the corner (where the edges separate) to the image border, every
// `spacing_px` of arc length. What tracking measures, and what overlays draw.
std::vector<Eigen::Vector2d> PredictEdgePx(const CameraIntrinsics& k, const CornerPose& pose,
                                           int axis, int spacing_px);

struct CornerTrackerOptions {
  int detect_every_n_frames = 30;    // a full detection at least this often (1: always detect)
  double search_half_width_px = 12;  // how far an edge may move between frames, pixels
  int spacing_px = 3;                // between edge points along an edge, whole pixels
  double min_coverage = 0.25;        // each edge found on at least this much of its prediction
};

class CornerTracker {
 public:
  CornerTracker(const CameraIntrinsics& intrinsics, double ceiling_distance_m,
                const CornerTrackerOptions& options = {},
                const CornerDetectorOptions& detector = {},
                const CornerQualityOptions& quality = {});

  // The pose in this frame; `source` says whether it was tracked or detected.
  Result<CornerLocation> Process(const cv::Mat& grey);

  // Why the last frame that could have been tracked was detected instead (empty: it was not).
  const std::string& fallback_reason() const { return fallback_reason_; }

  // Forget the last pose (the next frame is detected), e.g. after a gap in the stream.
  void Reset();

 private:
  Result<CornerLocation> Track(const cv::Mat& grey) const;

  CameraIntrinsics intrinsics_;
  double ceiling_distance_m_;
  CornerTrackerOptions options_;
  CornerDetectorOptions detector_;
  CornerQualityOptions quality_;
  std::optional<CornerPose> last_pose_;
  // From the last detection (CornerEdges' two): noise changes slowly.
  double noise_sigma_grey_ = 0, measurement_noise_grey_ = 0;
  int frames_since_detection_ = 0;
  std::string fallback_reason_;
};

}  // namespace monocle
