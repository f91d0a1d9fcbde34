// The Cramér–Rao bound on a corner pose from its three edges: how well ANY unbiased
// estimator could know the camera's x, y, pan, tilt and swing (the ceiling distance given)
// from the pixels along the Y, whatever detector it uses.
//
// Model, per edge point: the image across the edge is a step of contrast C blurred by a
// Gaussian of sigma s (defocus and the pixel's area), plus white noise of sigma n. The pixels
// across one unit of edge length then carry Fisher information C^2 / (2 sqrt(pi) s n^2) about
// the edge's position along its normal, so for the pose
//     I = sum over edge points of  dl * C^2 / (2 sqrt(pi) s n^2) * g g^T,
// with g the normal shift of the edge point per unit of each pose parameter. The shading,
// vignetting and hot-spot of a real room are unknown to a detector and carry no pose
// information here; only the edges do. The junction's few pixels, where the three blurs
// overlap, are left out. Everything is computed with the renderer's reference camera
// (cv::projectPoints), not the locator's code.
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"

namespace monocle::testing {

// Parameters in this order: camera x (m), y (m), pan, tilt, swing (rad).
using PoseVector = Eigen::Matrix<double, 5, 1>;
using PoseMatrix = Eigen::Matrix<double, 5, 5>;

struct EdgeSample {
  int axis = 0;                                      // 0: X, 1: Y, 2: Z edge
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();   // distorted pixel, OpenCV centres
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // unit, across the edge's image
  double length_px = 0;                              // image length this sample stands for
  PoseVector normal_shift_px = PoseVector::Zero();   // d(normal offset)/d(parameter)
};

// The visible parts of the three edges from the corner out to `edge_length_m` (X, Y, Z), in
// samples about 0.25 px apart, skipping `junction_px` around the corner. Points behind the
// camera or outside the image are left out.
std::vector<EdgeSample> SampleCornerEdges(const CameraIntrinsics& k, const CornerPose& pose,
                                          const std::array<double, 3>& edge_length_m,
                                          double junction_px = 3.0);

// Contrast of each sample in a noise-free render (8-bit or float): the difference of the image
// `offset_px` either side of the edge (grey levels, bilinear). 0 where either side is off the
// image.
std::vector<double> EdgeContrastGrey(const std::vector<EdgeSample>& samples,
                                     const cv::Mat& noise_free_grey, double offset_px = 5.0);

// Fisher information about the pose from the samples: blur `blur_sigma_px` (the Gaussian
// before the pixel grid; the pixel's own area is added), white noise `noise_sigma_grey`.
PoseMatrix CornerEdgeFisherInformation(const std::vector<EdgeSample>& samples,
                                       const std::vector<double>& contrast_grey,
                                       double blur_sigma_px, double noise_sigma_grey);

// The bound's covariance of the camera's horizontal position (x, y), m^2.
Eigen::Matrix2d HorizontalPositionBound(const PoseMatrix& information);

}  // namespace monocle::testing
