// Camera pose from one image of a ceiling corner: detection (corner_detector), line fits in
// undistorted coordinates, the paper's constrained refit, the closed form of
// service/geometry/corner_pose and its refinement; then how well the image supports the pose.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <numbers>
#include <opencv2/core.hpp>
#include <optional>
#include <ostream>
#include <string>

#include "service/common/result.h"
#include "service/geometry/base_in_corner.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/vision/corner_detector.h"

namespace monocle {

// How well one edge of the corner is seen.
struct EdgeSupport {
  double length_px = 0;          // corner to where its points stop following each other
  double visible_length_px = 0;  // how long the pose says the edge runs in the image
  double coverage = 0;           // fraction of the visible edge where points were measured
  double contrast_grey = 0;      // median step across the edge, grey levels
  double contrast_to_noise = 0;  // contrast_grey / CornerLocation::noise_sigma_grey
  double rms_px = 0;             // RMS distance of its points to the line the pose predicts
  double sigma_px = 0;           // 1 sigma of the fitted line's position at its middle
  double misfit_px = 0;          // how far its own line sits from the pose's (RMS over it)
  int points = 0;                // edge points used
  // The part of the horizontal position's variance, var(x) + var(y), that this edge's
  // measurement noise gives (0-1; the three add up to 1): the edge that limits the pose.
  // Of the pose from the image alone: the mount's level (corner_level.h) does not change it.
  double position_variance_share = 0;
};

// Whether the pose came from a full detection or from following the previous frame's edges.
enum class CornerSource { kDetected, kTracked };
const char* ToString(CornerSource source);
std::ostream& operator<<(std::ostream& os, CornerSource source);

struct CornerLocation {
  CornerPose pose;
  Eigen::Matrix<double, 5, 5> covariance;  // (x, y, pan, tilt, swing)
  // Orientation of the camera in the corner frame: v_corner = q * v_camera, with the camera
  // frame OpenCV's (x right, y down, z forward).
  Eigen::Quaterniond q_corner_camera;
  Eigen::Vector2d corner_px;                   // the corner as the refined pose projects it
  std::array<Eigen::Vector2d, 3> line_end_px;  // far end of the measured X, Y and Z edges
  std::array<int, 3> points_per_line{};        // inlier edge points of X, Y, Z
  double rms_px = 0;                           // RMS distance of edge points to the fitted lines
  std::array<EdgeSupport, 3> support;          // X, Y, Z
  // The image's noise as an edge measurement sees it (CornerEdges::measurement_noise_grey).
  double noise_sigma_grey = 0;
  // The strongest edge leaving the corner that is not one of the Y's (corner_rays.h): its
  // image angle (atan2 of its pixel direction) and step (grey levels; 0: none was read).
  double other_edge_angle_rad = 0;
  double other_edge_step_grey = 0;
  bool other_edge_flagged = false;  // it made the pose suspect (CornerQualityOptions)
  // Suspect: the edges do not support the pose consistently, or support it too weakly to
  // trust (see `suspect_reason`). Still a pose; never silently dropped or silently trusted.
  bool suspect = false;
  std::string suspect_reason;
  // How far the shading beside the edges moved the pose, (x, y, pan, tilt, swing) in metres
  // and radians: a one-sided shading slope across a faint edge moves all of its points the
  // same way (edge_profile.h, ShadingPeakShiftPx), which their scatter does not show. `pose`
  // is refined with each edge's points moved back by it, and its outer product is added to
  // `covariance`: the correction's own noise where there was no bias, more where there was.
  // Zero where it was not read: the pose's horizontal 1 sigma without it under
  // CornerQualityOptions::shading_check_above_relative_sigma.
  Eigen::Matrix<double, 5, 1> shading_shift = Eigen::Matrix<double, 5, 1>::Zero();
  // The view was weakly determined (CornerQualityOptions::remeasure_above_relative_sigma):
  // its blurred edges were measured again along the fitted lines with the wider filter
  // (WeakViewEdgeDerivativeSigmaPx), and the pose is from those points.
  bool edges_measured_again = false;
  // Suspect only because the view fixes the position weakly (its 1 sigma is over
  // CornerQualityOptions::max_relative_sigma): the edges agree with the pose and with each
  // other, so no other Y in the image would be the better answer.
  bool suspect_only_imprecise = false;
  CornerSource source = CornerSource::kDetected;
  // `covariance` includes the calibration's intrinsics uncertainty (the pipeline adds it
  // where the calibration has a covariance); false: the edges' measurement alone.
  bool sigma_includes_intrinsics = false;
  // With the mount's level (corner_level.h): how far the pose as solved tipped the robot
  // base from level, before the two were combined, and the level's 1 sigma (radians).
  std::optional<double> level_error_rad;
  double level_sigma_rad = 0;
  // With the camera's mount: the robot base in the corner frame, from the pose above.
  std::optional<BaseInCorner> base;
  CornerEdges edges;  // what the detector saw (overlays)

  Eigen::Matrix<double, 5, 1> Sigma() const { return covariance.diagonal().cwiseSqrt(); }
};

std::ostream& operator<<(std::ostream& os, const CornerLocation& c);

// When a pose is marked suspect.
struct CornerQualityOptions {
  double min_coverage = 0.3;  // an edge found on less of its visible length
  // An edge whose median step is below this many times the noise an edge measurement sees
  // (CornerLocation::noise_sigma_grey), not the pixel-to-pixel noise, which JPEG lowers 2-5x:
  // at 1, a raw frame and its JPEG are flagged alike.
  double min_contrast_to_noise = 1.0;
  // An edge whose own line sits further from the pose's line than this many of its 1 sigma
  // (and at least min_edge_misfit_px): the edges do not agree on one pose.
  double max_edge_misfit_sigmas = 4.0;
  double min_edge_misfit_px = 0.5;
  // Horizontal 1 sigma over the horizontal distance. Above 1.25 %, 5 % of the distance is
  // within 4 sigma, the product's "no pose more than 5 % off unflagged" with room for the weak
  // views' 1 sigma being a little optimistic; looser limits let poses over 5 % off go
  // unflagged (tests/accuracy/corner_pose_notes.md, "Conclusions").
  double max_relative_sigma = 0.0125;
  // The shading beside the edges is read and its shift of the pose removed (and counted in
  // the covariance, CornerLocation::shading_shift) where the horizontal 1 sigma without it is
  // over this fraction of the distance. Below 0.4 % a 5 % error would be 12 sigma, and on the
  // better determined views the correction's own noise is most of what it changes; reading it
  // on every frame would cost a third of a realistic frame's time (tests/accuracy/README.md).
  double shading_check_above_relative_sigma = 0.004;
  // Where the horizontal 1 sigma is over this fraction of the distance, the blurred edges are
  // measured again along the fitted lines with the wider filter
  // (WeakViewEdgeDerivativeSigmaPx) before the shading is read, and the pose refined from
  // them (CornerLocation::edges_measured_again). Below this it no longer lowers the errors
  // and would cost a third of a measurement on a quarter of realistic frames
  // (tests/accuracy/corner_pose_notes.md, "Weak views measured again, with a wider filter").
  // Infinity: never.
  double remeasure_above_relative_sigma = 0.006;
  // Three surfaces meet at a corner, so near it the largest of the three edges' steps equals
  // the other two combined. Measured it comes out smaller (down to -60 % on realistic
  // renders: blur mixes the three surfaces at the junction); larger by more than this
  // fraction of itself, one "edge" is not between those surfaces (a faint line of texture
  // or noise taken for the corner's edge).
  double max_step_excess = 0.4;
  // A camera on a robot stands upright give or take its mount's roll (the product's range is
  // +-30 degrees of swing). A pose rolled further is most likely another Y read as the
  // ceiling corner: a floor corner is a Y too, and the ceiling-corner pose that fits its
  // lines exactly rolls the camera over (68 degrees in the view that showed it). A camera
  // mounted rolled further than this would have every pose flagged: raise it there, with
  // corner { max_swing } in its calibration file.
  double max_swing_rad = 45 * std::numbers::pi / 180;
  // A ceiling corner has three edges. An edge leaving it that is not one of the Y's, with a
  // step (corner_rays.h) over this many times the Y's weakest and over
  // min_other_ray_noise_sigmas of the noise, means one of the corner's edges was taken for
  // something else. Where the Y is right the strongest other edge stays well below the
  // weakest; where a lost edge let a faint line stand in, it is several times stronger
  // (tests/accuracy/corner_pose_notes.md, "Wrong Ys").
  double max_other_ray_ratio = 1.5;
  double min_other_ray_noise_sigmas = 2;
};

// The reason a pose is flagged for its imprecision, when its horizontal 1 sigma is over
// quality.max_relative_sigma of its horizontal distance (empty otherwise). It is one of the
// reasons in CornerLocation::suspect_reason, kept apart so that a step that changes the
// 1 sigma afterwards (the mount's level) can state it again with the new figure.
// `qualifier`: said after "of the distance", e.g. "with the mount's level".
std::string ImprecisionReason(const CornerPose& pose, const Eigen::Matrix<double, 5, 5>& covariance,
                              const CornerQualityOptions& quality,
                              const std::string& qualifier = "");
// True for a reason ImprecisionReason wrote.
bool IsImprecisionReason(const std::string& reason);

Result<CornerLocation> LocateCorner(const cv::Mat& grey, const CameraIntrinsics& intrinsics,
                                    double ceiling_distance_m,
                                    const CornerDetectorOptions& options = {},
                                    const CornerQualityOptions& quality = {});

// The pose from edges already found (by the detector, or predicted by a tracker). With
// `previous`, edges[k] is axis k's and the refinement starts from that pose (no closed form).
Result<CornerLocation> LocateCornerFromEdges(const cv::Mat& grey,
                                             const CameraIntrinsics& intrinsics,
                                             double ceiling_distance_m, CornerEdges edges,
                                             const CornerDetectorOptions& options,
                                             const CornerQualityOptions& quality,
                                             const CornerPose* previous = nullptr);

}  // namespace monocle
