#include "service/vision/halve_image.h"

#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>

namespace monocle {
namespace {

// Eight 16-bit lanes, each holding two neighbouring pixels of a row (GCC's vector extension:
// SSE2 on x86, NEON on ARM). The 2 x 2 sum does not depend on which byte is which.
using PixelPairs = uint16_t __attribute__((vector_size(16)));
using Bytes8 = uint8_t __attribute__((vector_size(8)));

// How many source rows ahead to prefetch: fastest from 8 on, on a cold 1280 x 1024 frame
// (bench/corner_speed_notes.md).
constexpr int kPrefetchRows = 8;

}  // namespace

void HalveImage(const cv::Mat& src, cv::Mat* dst) {
  CV_Assert(src.type() == CV_8UC1);
  if (src.cols % 2 != 0 || src.rows % 2 != 0) {
    cv::resize(src, *dst, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    return;
  }
  dst->create(src.rows / 2, src.cols / 2, CV_8UC1);
  const int width = dst->cols;
  for (int y = 0; y < dst->rows; ++y) {
    const uint8_t* top = src.ptr<uint8_t>(2 * y);
    const uint8_t* bottom = src.ptr<uint8_t>(2 * y + 1);
    uint8_t* out = dst->ptr<uint8_t>(y);
    if (2 * y + 1 + kPrefetchRows < src.rows) {
      const uint8_t* next_top = src.ptr<uint8_t>(2 * y + kPrefetchRows);
      const uint8_t* next_bottom = src.ptr<uint8_t>(2 * y + 1 + kPrefetchRows);
      for (int x = 0; x < src.cols; x += 64) {  // a cache line each
        __builtin_prefetch(next_top + x);
        __builtin_prefetch(next_bottom + x);
      }
    }
    int x = 0;
    for (; x + 8 <= width; x += 8) {
      PixelPairs a, b;
      std::memcpy(&a, top + 2 * x, sizeof a);
      std::memcpy(&b, bottom + 2 * x, sizeof b);
      const PixelPairs sum = (a & 0xFF) + (a >> 8) + (b & 0xFF) + (b >> 8) + 2;
      const Bytes8 mean = __builtin_convertvector(sum >> 2, Bytes8);
      std::memcpy(out + x, &mean, sizeof mean);
    }
    for (; x < width; ++x) {
      out[x] = static_cast<uint8_t>(
          (top[2 * x] + top[2 * x + 1] + bottom[2 * x] + bottom[2 * x + 1] + 2) >> 2);
    }
  }
}

}  // namespace monocle
