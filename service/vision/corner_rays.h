// The edges that leave a point, read off rings around it: whether a Y's three edges are the
// strongest there. A ceiling corner is where exactly three surfaces meet, so around it the
// image changes across three rays and nowhere else; a ray stronger than one of the Y's edges
// means a Y was taken with a wrong third edge (at quarter resolution a short, strong edge
// can be lost while a faint line into glare stands in for it, a pose far off that nothing
// else flags: tests/accuracy/corner_pose_notes.md, "Wrong Ys").
//
// Clutter does not make a ray: a cable, a frame or a picture edge crosses each ring at an
// angle that changes with the ring's radius, and a ray must show its step on nearly every ring.
// Slow light (glare, vignetting, shading) changes little over the few pixels a step spans.
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>

namespace monocle {

struct RayProfileOptions {
  // Rings from this radius to max_radius_px, radius_step_px apart (pixels). Inside the
  // smallest, the three edges' blurred steps overlap.
  double min_radius_px = 24;
  double max_radius_px = 96;
  double radius_step_px = 8;
  // A step at an arc position is the mean over [gap, gap + width] px along the ring on one
  // side minus that on the other: the gap clears an edge's blur.
  double step_gap_px = 2;
  double step_width_px = 5;
  // Rays within this of one of the Y's edges are that edge (degrees; plus the arc the step
  // windows span at each radius).
  double exclude_deg = 3;
  // A ray is read only where at least this fraction of its rings lie in the image.
  double min_ring_fraction = 0.5;
  // The Y's edges are read as the median step over the rings. Another ray's step is the one
  // all but this fraction of the rings show: a straight line passing near the corner crosses
  // a run of rings at nearly one angle (at r its angle is off by asin(distance / r)), and a
  // picture frame 20 px from a corner made a median "ray" of 53 grey levels.
  double other_ray_quantile = 0.2;
};

struct OtherRay {
  double angle_rad = 0;  // image angle (atan2 of dy, dx in pixels) of the strongest other ray
  double step_grey = 0;  // its step: median over the rings, grey levels (0: none measured)
  std::array<double, 3> edge_step_grey{};  // the Y's own edges, measured the same way
};

// A pixel `distance_px` along the ray at image angle `angle_rad` from `corner_px`: where to
// say it runs.
Eigen::Vector2d OtherEdgeTowardsPx(const Eigen::Vector2d& corner_px, double angle_rad,
                                   double distance_px = 100);

// The strongest ray leaving `corner_px` other than the three of `edge_direction_px` (unit,
// pixels, leaving the corner), and the three edges' steps measured the same way.
OtherRay StrongestOtherRay(const cv::Mat& grey, const Eigen::Vector2d& corner_px,
                           const std::array<Eigen::Vector2d, 3>& edge_direction_px,
                           const RayProfileOptions& options = {});

}  // namespace monocle
