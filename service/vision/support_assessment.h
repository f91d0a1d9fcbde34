// How well the three edges support a located corner pose: per edge its length, coverage,
// contrast against the noise and misfit to the pose's line, and the reasons, in words, to
// call the pose suspect (an edge barely found or off its line, steps that do not add up, a
// stronger fourth edge, a roll no ceiling corner gives, or only imprecision).
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "service/geometry/camera_model.h"
#include "service/vision/corner_locator.h"
#include "service/vision/edge_line_fit.h"

namespace monocle {

// A whole edge may sit this far (1 sigma, pixels) from where its points say: shading that
// differs across the edge, JPEG blocks and blur shift the steepest rise a little, the same
// way along the whole edge (a surface seen at a grazing angle, brightening towards the edge on
// one side only). Chosen so the reported 1 sigma covers about 68 % of the errors on the
// development renders; the accuracy test checks it on others (tests/accuracy/corner_pose_notes.md,
// "Measuring each point better, a third time").
inline constexpr double kLineBiasPx = 0.05;

// Fills `out`'s support, line ends, rms and suspicion from the three edges' fits against the
// refined pose already in `out` (pose, covariance, corner_px, noise_sigma_grey).
// `axis_of_line[m]` is the axis fit m images; `corner_n` the corner in normalized
// coordinates; `spacing_px` each edge's point spacing.
void AssessSupport(const cv::Mat& grey, const CameraIntrinsics& k,
                   const std::array<LineFit, 3>& fits, const std::array<int, 3>& axis_of_line,
                   const Eigen::Vector2d& corner_n, const CornerQualityOptions& quality,
                   const std::array<double, 3>& spacing_px, CornerLocation* out);

}  // namespace monocle
