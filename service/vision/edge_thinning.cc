#include "service/vision/edge_thinning.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "service/vision/order_statistics.h"

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

// Four int32 lanes, compared all at once (GCC's vector extension).
using Lanes4 = int32_t __attribute__((vector_size(16)));

std::vector<EdgePixel> ThinEdges(const cv::Mat& img, const CornerDetectorOptions& options) {
  cv::Mat gx, gy;
  cv::spatialGradient(img, gx, gy);  // 3x3 Sobel in x and y in one pass
  const int w = img.cols, h = img.rows;
  auto squared = [](int16_t x, int16_t y) { return int32_t{x} * x + int32_t{y} * y; };
  std::vector<int32_t> sample;
  sample.reserve(static_cast<size_t>(w) * h / 16 + 16);
  for (int y = 2; y < h; y += 4) {
    const auto* px = gx.ptr<int16_t>(y);
    const auto* py = gy.ptr<int16_t>(y);
    for (int x = 2; x < w - 2; x += 4) sample.push_back(squared(px[x], py[x]));
  }
  double noise2 = 0;  // sigma_g^2
  if (!sample.empty()) noise2 = MedianOfNonNegative(sample) / (2 * std::log(2.0));
  const double threshold2 = std::max(options.edge_snr * options.edge_snr * noise2,
                                     options.min_edge_gradient * options.min_edge_gradient);
  const int32_t t2 = static_cast<int32_t>(std::min(threshold2, 2e9));
  std::vector<EdgePixel> out;
  if (w < 3 || h < 3) return out;
  const double noise = std::sqrt(noise2);
  // Squared magnitudes of rows y - 1, y and y + 1, in a ring of three.
  std::vector<int32_t> ring(3 * static_cast<size_t>(w));
  auto mag_row = [&](int y) { return &ring[static_cast<size_t>(y % 3) * w]; };
  auto fill = [&](int y) {
    const auto* px = gx.ptr<int16_t>(y);
    const auto* py = gy.ptr<int16_t>(y);
    int32_t* m = mag_row(y);
    for (int x = 0; x < w; ++x) m[x] = squared(px[x], py[x]);
  };
  fill(0);
  fill(1);
  std::vector<int> above(static_cast<size_t>(w));
  for (int y = 1; y < h - 1; ++y) {
    fill(y + 1);
    const auto* px = gx.ptr<int16_t>(y);
    const auto* py = gy.ptr<int16_t>(y);
    const int32_t* m = mag_row(y);
    const int32_t* up = mag_row(y - 1);
    const int32_t* down = mag_row(y + 1);
    // The columns at or above the threshold: 16 tested at once, in four-lane vectors (GCC's
    // vector extension: SSE2 here, NEON on ARM; the compiler did not vectorize the plain
    // loop), and only a block holding one listed pixel by pixel, without a branch per pixel.
    size_t count = 0;
    int x = 1;
    for (; x + 16 <= w - 1; x += 16) {
      Lanes4 any = {0, 0, 0, 0};
      for (int k = 0; k < 16; k += 4) {
        Lanes4 v;
        std::memcpy(&v, m + x + k, sizeof v);
        any |= v >= t2;
      }
      if ((any[0] | any[1] | any[2] | any[3]) == 0) continue;
      for (int k = 0; k < 16; ++k) {
        above[count] = x + k;
        count += m[x + k] >= t2;
      }
    }
    for (; x < w - 1; ++x) {
      above[count] = x;
      count += m[x] >= t2;
    }
    for (size_t i = 0; i < count; ++i) {
      const int x = above[i];
      const int32_t v = m[x];
      const int ax = std::abs(px[x]), ay = std::abs(py[x]);
      int32_t n1, n2;
      if (ay * 1000 < ax * 414) {  // gradient within 22.5 degrees of horizontal
        n1 = m[x - 1];
        n2 = m[x + 1];
      } else if (ax * 1000 < ay * 414) {  // near vertical
        n1 = up[x];
        n2 = down[x];
      } else if ((px[x] > 0) == (py[x] > 0)) {  // diagonal down-right
        n1 = up[x - 1];
        n2 = down[x + 1];
      } else {
        n1 = up[x + 1];
        n2 = down[x - 1];
      }
      if (v < n1 || v <= n2) continue;
      const float norm = std::sqrt(static_cast<float>(v));
      // The gradient's direction is uncertain by ~sigma_g / |g| rad: a weak edge's pixels
      // vote over a wider range of angles, or they never meet in one Hough cell.
      const double angle_sigma_bins = noise / norm * kAngleBins / kPi;
      const int window = std::clamp(static_cast<int>(std::ceil(2 * angle_sigma_bins)),
                                    kMinVoteHalfWindow, kMaxVoteHalfWindow);
      out.push_back(
          {static_cast<float>(x), static_cast<float>(y), px[x] / norm, py[x] / norm, window});
    }
  }
  return out;
}

}  // namespace monocle::corner_detection
