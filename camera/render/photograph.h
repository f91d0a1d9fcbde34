// What a camera does to the light of a rendered scene: vignetting, a lamp's hot-spot,
// defocus, sensor noise and JPEG compression. Shared by the corner and board renderers.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

namespace monocle {

struct PhotoEffects {
  double vignetting = 0;  // fraction darker at the image's corners (cos^4-like falloff)
  Eigen::Vector2d hotspot_px = Eigen::Vector2d::Zero();  // a broad lamp glare
  double hotspot_radius_px = 1;                          // its Gaussian sigma
  double hotspot_gain = 0;                               // relative brightening at its centre
  double blur_sigma_px = 0;                              // defocus, Gaussian
  double noise_sigma = 0;                                // sensor noise, grey levels
  int jpeg_quality = 0;                                  // 0: not compressed
};

// `radiance`: CV_32F grey levels. Returns the 8-bit image the camera delivers.
cv::Mat Photograph(const cv::Mat& radiance, const PhotoEffects& effects, uint64_t seed);

// The light on the sensor, CV_32F grey levels: vignetting, hot-spot and blur, before noise,
// rounding and JPEG. Photograph's image is this plus noise, rounded, compressed. For tests
// that differentiate a render with respect to the pose, where rounding would add noise.
cv::Mat Expose(const cv::Mat& radiance, const PhotoEffects& effects);

}  // namespace monocle
