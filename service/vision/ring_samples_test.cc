#include "service/vision/ring_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace monocle {
namespace {

// The image at (x, y), bilinearly, in double precision; false where the read leaves it.
bool ReferenceBilinear(const cv::Mat& grey, double x, double y, double* out) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= grey.cols || y0 + 1 >= grey.rows) return false;
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int u, int v) { return static_cast<double>(grey.at<uint8_t>(v, u)); };
  *out = (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
  return true;
}

cv::Mat NoiseImage() {
  cv::Mat grey(240, 320, CV_8UC1);
  cv::RNG rng(5);
  rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
  return grey;
}

// Sample i of a ring: 2 pi i / samples counter-clockwise from +x, `radius_px` from `centre`.
Eigen::Vector2d SamplePosition(const Eigen::Vector2d& centre, double radius_px, int i,
                               int samples) {
  const double angle = 2 * std::numbers::pi * i / samples;
  return centre + radius_px * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

TEST(RingSamplesTest, ARingInsideTheImageIsReadBilinearly) {
  const cv::Mat grey = NoiseImage();
  const Eigen::Vector2d centre(160.3, 118.7);
  for (double radius_px : {24.0, 56.0, 96.0}) {
    ASSERT_TRUE(RingInsideImage(grey, centre, radius_px));
    const int samples = static_cast<int>(std::ceil(2 * std::numbers::pi * radius_px));
    std::vector<float> value(samples);
    SampleRing(grey, centre, radius_px, samples, value.data(), nullptr);
    for (int i = 0; i < samples; ++i) {
      const Eigen::Vector2d p = SamplePosition(centre, radius_px, i, samples);
      double expected;
      ASSERT_TRUE(ReferenceBilinear(grey, p.x(), p.y(), &expected));
      // In float, a sample's position is off by ~1e-5 px: 0.01 grey levels at most on noise.
      ASSERT_NEAR(value[i], expected, 0.05) << "radius " << radius_px << ", sample " << i;
    }
  }
}

TEST(RingSamplesTest, ARingLeavingTheImageSaysWhichSamplesWereRead) {
  const cv::Mat grey = NoiseImage();
  const Eigen::Vector2d centre(20.5, 200.25);
  const double radius_px = 40;
  ASSERT_FALSE(RingInsideImage(grey, centre, radius_px));
  const int samples = 252;
  std::vector<float> value(samples, -1);
  std::vector<uint8_t> ok(samples, 7);
  SampleRing(grey, centre, radius_px, samples, value.data(), ok.data());
  int read = 0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d p = SamplePosition(centre, radius_px, i, samples);
    double expected;
    const bool inside = ReferenceBilinear(grey, p.x(), p.y(), &expected);
    ASSERT_EQ(ok[i], inside ? 1 : 0) << i;
    ASSERT_NEAR(value[i], inside ? expected : 0.0, 1e-3) << i;
    read += inside;
  }
  EXPECT_GT(read, samples / 4);
  EXPECT_LT(read, samples);
}

}  // namespace
}  // namespace monocle
