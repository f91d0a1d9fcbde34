#include "service/vision/image_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

namespace monocle {

namespace {

// Pixels at the sensor's limits (a lamp's glare, a black hole): their noise is clipped away, so
// the noise estimates leave out every difference that touches one (>= 253 or <= 2 grey: JPEG
// rounds a clipped white surface to 253-255). Otherwise a frame mostly clipped white reads
// almost no noise, and every edge stands far out of it (image_noise_test).
constexpr uint8_t kSaturatedWhite = 253, kSaturatedBlack = 2;
bool Saturated(uint8_t v) { return v >= kSaturatedWhite || v <= kSaturatedBlack; }

// Sixteen bytes, compared and subtracted all at once (GCC's vector extension: SSE2 on x86,
// NEON on ARM).
using Bytes16 = uint8_t __attribute__((vector_size(16)));

// Whether any of the n pixels from `p` is saturated, 16 at a time.
bool AnySaturated(const uint8_t* p, int n) {
  Bytes16 hits{};  // lanes OR-ed over the whole span, tested once: no branch per 16 pixels
  int x = 0;
  for (; x + 16 <= n; x += 16) {
    Bytes16 v;
    std::memcpy(&v, p + x, 16);
    hits |= reinterpret_cast<Bytes16>((v >= kSaturatedWhite) | (v <= kSaturatedBlack));
  }
  uint64_t halves[2];
  std::memcpy(halves, &hits, 16);
  if (halves[0] | halves[1]) return true;
  for (; x < n; ++x)
    if (Saturated(p[x])) return true;
  return false;
}

// The rows EstimateNoiseSigma reads: every fourth, every eighth from 512 rows (still 80 000
// differences, and a tenth of a detection's time less).
int NoiseRowStep(const cv::Mat& grey) { return grey.rows >= 512 ? 8 : 4; }

// The histogram of |I(x+1) - I(x)| over those rows, saturated pixels left out. Four histograms
// filled in turn, summed after: consecutive increments of one bin (most differences are 0-3)
// otherwise wait for each other. Only the median's fall-back when it lies beyond the small
// bins (a rough image), so plainly written.
std::array<int64_t, 256> DifferenceHistogram(const cv::Mat& grey) {
  std::array<std::array<int32_t, 256>, 4> partial{};
  for (int y = 1; y < grey.rows; y += NoiseRowStep(grey)) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    for (int x = 0; x + 1 < grey.cols; ++x)
      if (!Saturated(row[x]) && !Saturated(row[x + 1]))
        ++partial[x & 3][std::abs(row[x + 1] - row[x])];
  }
  std::array<int64_t, 256> histogram{};
  for (const auto& h : partial)
    for (int d = 0; d < 256; ++d) histogram[d] += h[d];
  return histogram;
}

// The same histogram's first kSmallBins bins, exactly, and the count beyond them: 16
// differences at a time, counted per bin in byte lanes. Most of a room is flat, so the
// median difference is one of these bins and the rest of the histogram is never needed
// (this took a third of DifferenceHistogram's time).
constexpr int kSmallBins = 8;
std::array<int64_t, kSmallBins + 1> SmallDifferenceCounts(const cv::Mat& grey) {
  std::array<int64_t, kSmallBins + 1> counts{};  // the last: kSmallBins and more
  std::array<Bytes16, kSmallBins> lanes{};
  Bytes16 counted_lanes{};  // differences between two unsaturated pixels, in rows that have any
  int64_t counted = 0;
  int chunks = 0;
  auto flush = [&] {
    for (int d = 0; d < kSmallBins; ++d) {
      for (int lane = 0; lane < 16; ++lane) counts[d] += lanes[d][lane];
      lanes[d] = Bytes16{};
    }
    for (int lane = 0; lane < 16; ++lane) counted += counted_lanes[lane];
    counted_lanes = Bytes16{};
    chunks = 0;
  };
  // One row's 16-wide part; kMasked: the row holds saturated pixels, so each difference is
  // counted only between two unsaturated ones (most rows hold none and skip the masking).
  auto count_row = [&]<bool kMasked>(const uint8_t* row) {
    int x = 0;
    for (; x + 16 < grey.cols; x += 16) {
      Bytes16 a, b;
      std::memcpy(&a, row + x, 16);
      std::memcpy(&b, row + x + 1, 16);
      const Bytes16 difference = (a > b) ? Bytes16(a - b) : Bytes16(b - a);
      if constexpr (kMasked) {
        const Bytes16 high = (a > b) ? a : b, low = (a > b) ? b : a;
        const auto unsaturated = (high < kSaturatedWhite) & (low > kSaturatedBlack);  // -1 / 0
        counted_lanes -= reinterpret_cast<Bytes16>(unsaturated);
        for (int d = 0; d < kSmallBins; ++d)  // -1: +1
          lanes[d] -=
              reinterpret_cast<Bytes16>((difference == static_cast<uint8_t>(d)) & unsaturated);
      } else {
        counted += 16;
        for (int d = 0; d < kSmallBins; ++d)  // -1: +1
          lanes[d] -= reinterpret_cast<Bytes16>(difference == static_cast<uint8_t>(d));
      }
      if (++chunks == 255) flush();  // before a byte lane can overflow
    }
    return x;
  };
  for (int y = 1; y < grey.rows; y += NoiseRowStep(grey)) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    int x = AnySaturated(row, grey.cols) ? count_row.template operator()<true>(row)
                                         : count_row.template operator()<false>(row);
    for (; x + 1 < grey.cols; ++x) {
      if (Saturated(row[x]) || Saturated(row[x + 1])) continue;
      ++counted;
      const int d = std::abs(row[x + 1] - row[x]);
      if (d < kSmallBins) ++counts[d];
    }
  }
  flush();
  int64_t small = 0;
  for (int d = 0; d < kSmallBins; ++d) small += counts[d];
  counts[kSmallBins] = counted - small;
  return counts;
}

// The median of a histogram of integer differences, interpolated within its bin (a few grey
// levels of noise give only a few distinct differences): bin d spans [d - 0.5, d + 0.5)
// (bin 0: [0, 0.5)). nullopt if it lies beyond the bins given.
template <size_t N>
std::optional<double> InterpolatedMedian(const std::array<int64_t, N>& histogram, int bins,
                                         int64_t count) {
  const double half = 0.5 * static_cast<double>(count);
  double below = 0;
  for (int d = 0; d < bins; ++d) {
    if (below + static_cast<double>(histogram[d]) >= half) {
      const double lo = d == 0 ? 0.0 : d - 0.5, width = d == 0 ? 0.5 : 1.0;
      return lo + width * (half - below) / std::max<double>(static_cast<double>(histogram[d]), 1);
    }
    below += static_cast<double>(histogram[d]);
  }
  return std::nullopt;
}

}  // namespace

double EstimateNoiseSigma(const cv::Mat& grey) {
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols < 2) return 0;
  // The median absolute difference of neighbouring pixels along rows.
  const auto small = SmallDifferenceCounts(grey);
  int64_t count = 0;
  for (const int64_t c : small) count += c;
  auto median = InterpolatedMedian(small, kSmallBins, count);
  if (!median) median = InterpolatedMedian(DifferenceHistogram(grey), 256, count);
  // Median of |N(0, 2 sigma^2)| is 0.6745 * sqrt(2) sigma.
  return median.value_or(0) / (0.6745 * std::sqrt(2.0));
}

double EstimateMeasurementNoiseSigma(const cv::Mat& grey) {
  constexpr int kRun = 8;  // pixels per mean
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols < 3 * kRun) return 0;
  // Second differences of neighbouring means: a linear shading cancels, an edge is one of
  // many (the median ignores it). For white noise sigma a mean has variance sigma^2 / 8 and
  // m[i-1] - 2 m[i] + m[i+1] has 6 sigma^2 / 8. They are histogrammed as sums (integers; a
  // grey level of the means is 8 bins) and the median interpolated within its bin, as in
  // EstimateNoiseSigma.
  constexpr int kBins = 1024;  // second differences of sums beyond 1023 (128 grey) are edges
  std::array<int32_t, kBins> histogram{};
  int64_t count = 0;
  const int runs = grey.cols / kRun;
  const int row_step = grey.rows >= 512 ? 16 : 4;  // 1280x1024: 64 rows, 10 000 differences
  thread_local std::vector<int32_t> sums;
  thread_local std::vector<uint8_t> saturated;  // the run holds a saturated pixel
  sums.resize(runs);
  saturated.resize(runs);
  for (int y = row_step / 2; y < grey.rows; y += row_step) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    for (int i = 0; i < runs; ++i) {
      int32_t sum = 0;
      for (int j = 0; j < kRun; ++j) sum += row[i * kRun + j];
      sums[i] = sum;
    }
    auto second_difference = [&](int i) {
      return std::min(std::abs(sums[i - 1] - 2 * sums[i] + sums[i + 1]), kBins - 1);
    };
    if (!AnySaturated(row, runs * kRun)) {  // most rows: one vector pass says so
      for (int i = 1; i + 1 < runs; ++i) ++histogram[second_difference(i)];
      count += runs - 2;
      continue;
    }
    for (int i = 0; i < runs; ++i) saturated[i] = AnySaturated(row + i * kRun, kRun);
    for (int i = 1; i + 1 < runs; ++i) {
      if (saturated[i - 1] || saturated[i] || saturated[i + 1]) continue;
      ++histogram[second_difference(i)];
      ++count;
    }
  }
  if (count == 0) return 0;
  const double half = 0.5 * static_cast<double>(count);
  double below = 0, median_of_sums = 0;
  for (int d = 0; d < kBins; ++d) {
    if (below + histogram[d] >= half) {
      const double lo = d == 0 ? 0.0 : d - 0.5, width = d == 0 ? 0.5 : 1.0;
      median_of_sums = lo + width * (half - below) / std::max<double>(histogram[d], 1);
      break;
    }
    below += histogram[d];
  }
  // Median of |N(0, 6 sigma^2 / 8)| is 0.6745 sqrt(6 / 8) sigma.
  const double median_of_means = median_of_sums / kRun;
  return median_of_means / (0.6745 * std::sqrt(6.0 / kRun));
}

}  // namespace monocle
