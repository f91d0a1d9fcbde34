#include "service/vision/ring_samples.h"

#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "service/vision/pixel_pairs.h"

namespace monocle {
namespace {

// The unit directions of a ring of `samples` samples, counter-clockwise from angle 0, as
// separate x and y in float: built once per thread for each sample count (as
// corner_rays.cc does its bins), so that no sample's position waits on the one before it.
struct RingDirections {
  std::vector<float> x, y;
};
const RingDirections& DirectionsOfSamples(int samples) {
  thread_local std::map<int, RingDirections> tables;
  auto [at, added] = tables.try_emplace(samples);
  if (added) {
    for (int i = 0; i < samples; ++i) {
      const double angle = 2 * std::numbers::pi * i / samples;
      at->second.x.push_back(static_cast<float>(std::cos(angle)));
      at->second.y.push_back(static_cast<float>(std::sin(angle)));
    }
  }
  return at->second;
}

// A ring wholly inside the image, read in float in three simple loops (positions, then
// pixel_pairs.h's gather and blend), as MeasureEdgeStretch reads its patches.
void SampleRingInside(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px,
                      const RingDirections& direction, float* value) {
  const int n = static_cast<int>(direction.x.size());
  thread_local std::vector<float> fx, fy;
  thread_local std::vector<int32_t> offset;
  thread_local std::vector<uint16_t> top_pair, bottom_pair;  // left | right << 8
  if (offset.size() < static_cast<size_t>(n)) {  // grown, never shrunk (no zeroing per ring)
    for (auto* v : {&fx, &fy}) v->resize(n);
    offset.resize(n);
    top_pair.resize(n);
    bottom_pair.resize(n);
  }
  const float cx = static_cast<float>(centre.x()), cy = static_cast<float>(centre.y());
  const float r = static_cast<float>(radius_px);
  const int32_t stride = static_cast<int32_t>(grey.step[0]);
  for (int i = 0; i < n; ++i) {
    const float x = cx + r * direction.x[i], y = cy + r * direction.y[i];
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);  // x, y >= 0: the floor
    fx[i] = x - static_cast<float>(x0);
    fy[i] = y - static_cast<float>(y0);
    offset[i] = y0 * stride + x0;
  }
  GatherPixelPairs(grey.data, stride, offset.data(), n, top_pair.data(), bottom_pair.data());
  BlendPixelPairs(top_pair.data(), bottom_pair.data(), fx.data(), fy.data(), n, value);
}

}  // namespace

bool RingInsideImage(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px) {
  return centre.x() - radius_px - 1 >= 0 && centre.y() - radius_px - 1 >= 0 &&
         centre.x() + radius_px + 2 < grey.cols && centre.y() + radius_px + 2 < grey.rows;
}

void SampleRing(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px, int samples,
                float* value, uint8_t* ok) {
  const RingDirections& direction = DirectionsOfSamples(samples);
  if (ok == nullptr) {
    SampleRingInside(grey, centre, radius_px, direction, value);
    return;
  }
  for (int i = 0; i < samples; ++i) {
    value[i] = 0;
    ok[i] = 0;
    const double x = centre.x() + radius_px * direction.x[i],
                 y = centre.y() + radius_px * direction.y[i];
    // Truncation is the floor for x, y >= 0; anything below 0 is skipped either way.
    if (!(x >= 0 && y >= 0)) continue;
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    if (x0 + 1 >= grey.cols || y0 + 1 >= grey.rows) continue;
    const double fx = x - x0, fy = y - y0;
    const uint8_t* r0 = grey.ptr<uint8_t>(y0) + x0;
    const uint8_t* r1 = grey.ptr<uint8_t>(y0 + 1) + x0;
    value[i] = static_cast<float>((1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) +
                                  fy * ((1 - fx) * r1[0] + fx * r1[1]));
    ok[i] = 1;
  }
}

}  // namespace monocle
