#include "service/vision/order_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace monocle {

int32_t MedianOfNonNegative(const std::vector<int32_t>& values) {
  constexpr int32_t kBins = 4096;
  thread_local std::vector<int32_t> histogram;
  histogram.assign(kBins, 0);
  size_t larger = 0;
  for (const int32_t v : values) {
    if (v < kBins) {
      ++histogram[v];
    } else {
      ++larger;
    }
  }
  const size_t rank = values.size() / 2;  // 0-based rank of the median
  size_t below = 0;
  for (int32_t v = 0; v < kBins; ++v) {
    below += static_cast<size_t>(histogram[v]);
    if (below > rank) return v;
  }
  // The median is among the values >= kBins: below == values.size() - larger.
  std::vector<int32_t> big;
  big.reserve(larger);
  for (const int32_t v : values)
    if (v >= kBins) big.push_back(v);
  const size_t big_rank = rank - below;
  std::nth_element(big.begin(), big.begin() + static_cast<std::ptrdiff_t>(big_rank), big.end());
  return big[big_rank];
}

void SortByPosition(std::vector<std::pair<double, Eigen::Vector2d>>* support) {
  auto& v = *support;
  if (v.size() < 2) return;
  double lo = v[0].first, hi = v[0].first;
  bool finite = true;
  for (const auto& e : v) {
    lo = std::min(lo, e.first);
    hi = std::max(hi, e.first);
    finite &= std::isfinite(e.first);
  }
  constexpr double kBinPx = 2;
  const double span_bins = (hi - lo) / kBinPx;
  if (!finite || span_bins > 8.0 * static_cast<double>(v.size()) + 64) {  // sparse: sort
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return;
  }
  const size_t bins = static_cast<size_t>(span_bins) + 1;
  thread_local std::vector<uint32_t> next;  // first free slot of each bin
  thread_local std::vector<std::pair<double, Eigen::Vector2d>> binned;
  next.assign(bins + 1, 0);
  auto bin = [&](double t) { return std::min(static_cast<size_t>((t - lo) / kBinPx), bins - 1); };
  for (const auto& e : v) ++next[bin(e.first) + 1];
  for (size_t b = 1; b <= bins; ++b) next[b] += next[b - 1];
  binned.resize(v.size());
  for (const auto& e : v) binned[next[bin(e.first)]++] = e;
  for (size_t i = 1; i < binned.size(); ++i) {
    const auto e = binned[i];
    size_t j = i;
    for (; j > 0 && e.first < binned[j - 1].first; --j) binned[j] = binned[j - 1];
    binned[j] = e;
  }
  v.swap(binned);
}

}  // namespace monocle
