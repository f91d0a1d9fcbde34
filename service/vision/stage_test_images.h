// Images for the corner detector's stage tests: a half-plane step (bright where
// x cos(a) + y sin(a) > rho), blurred as a camera blurs it, with seeded noise.
#pragma once

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace monocle::testing {

inline cv::Mat HalfPlaneStep(int width, int height, double angle_rad, double rho_px,
                             double dark_grey, double bright_grey, double blur_sigma_px,
                             double noise_sigma_grey, uint64_t seed) {
  cv::Mat f(height, width, CV_32F);
  // 4x4 supersampling, so the step sits where the formula says to a small fraction of a pixel.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      int bright = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const double px = x - 0.375 + 0.25 * sx, py = y - 0.375 + 0.25 * sy;
          bright += px * std::cos(angle_rad) + py * std::sin(angle_rad) > rho_px;
        }
      f.at<float>(y, x) = static_cast<float>(dark_grey + (bright_grey - dark_grey) * bright / 16.0);
    }
  if (blur_sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), blur_sigma_px);
  if (noise_sigma_grey > 0) {
    cv::Mat noise(height, width, CV_32F);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::NORMAL, 0, noise_sigma_grey);
    f += noise;
  }
  cv::Mat grey;
  f.convertTo(grey, CV_8U);
  return grey;
}

}  // namespace monocle::testing
