// Images of straight edges for the vision tests: steps blurred as a camera blurs them, with
// seeded noise, each edge where its formula puts it to a small fraction of a pixel.
#pragma once

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace monocle::testing {

// `image` (float grey levels) with Gaussian noise of `noise` added, as an 8-bit camera gives it.
inline cv::Mat WithNoiseAs8Bit(cv::Mat image, double noise, uint64_t seed) {
  if (noise > 0) {
    cv::Mat n(image.size(), CV_32F);
    cv::RNG rng(seed);
    rng.fill(n, cv::RNG::NORMAL, 0.0, noise);
    image += n;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

// A straight step edge of `step` grey levels through (edge_x, 0) at angle `angle` from the
// vertical, blurred by `blur` px, with Gaussian noise: each pixel integrates the step
// analytically (erf), so the edge sits at its true subpixel place.
inline cv::Mat StepImage(double edge_x, double angle, double step, double blur, double noise,
                         uint64_t seed, double dark_grey = 120) {
  cv::Mat image(400, 400, CV_32F);
  const double c = std::cos(angle), s = std::sin(angle);
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const double distance = (u - edge_x) * c - (v - 200) * s;  // signed, along the normal
      const double sigma = std::hypot(blur, 0.3);  // 0.3: a pixel's own extent, roughly
      image.at<float>(v, u) = static_cast<float>(
          dark_grey + step * 0.5 * (1 + std::erf(distance / (std::sqrt(2.0) * sigma))));
    }
  }
  return WithNoiseAs8Bit(image, noise, seed);
}

// A half-plane step (bright where x cos(a) + y sin(a) > rho), supersampled 4x4, blurred and
// with noise.

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
