// MedianOfNonNegative against std::nth_element and SortByPosition against std::sort, on the
// kinds of values the detector gives them and on the cases that take the other path: medians
// beyond the counted bins, sparse and non-finite positions, ties, one and two elements.
#include "service/vision/order_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

namespace monocle {
namespace {

int32_t NthElementMedian(std::vector<int32_t> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

TEST(OrderStatisticsTest, MedianIsNthElements) {
  std::mt19937 rng(7);
  int beyond_bins = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const size_t n = 1 + rng() % 600;
    // Squared gradients: mostly small (flat surfaces), some large (edges); every fourth trial
    // mostly large, so the median lies beyond the 4096 counted values.
    const int32_t typical = trial % 4 == 0 ? 200000 : 300;
    std::vector<int32_t> values(n);
    for (auto& v : values)
      v = rng() % 10 == 0 ? static_cast<int32_t>(rng() % 2000000)
                          : static_cast<int32_t>(rng() % typical);
    const int32_t expected = NthElementMedian(values);
    ASSERT_EQ(MedianOfNonNegative(values), expected) << "trial " << trial << ", n " << n;
    beyond_bins += expected >= 4096;
  }
  EXPECT_GT(beyond_bins, 50) << "the nth_element path was not exercised";
  EXPECT_EQ(MedianOfNonNegative({5}), 5);
  EXPECT_EQ(MedianOfNonNegative({9, 1}), 9);
  EXPECT_EQ(MedianOfNonNegative({4095, 4096, 4096}), 4096);
}

using Support = std::vector<std::pair<double, Eigen::Vector2d>>;

Support Sorted(Support v) {
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return v;
}

void ExpectSortedAsStd(const Support& input, const std::string& what) {
  Support ours = input;
  SortByPosition(&ours);
  const Support theirs = Sorted(input);
  ASSERT_EQ(ours.size(), theirs.size()) << what;
  for (size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(ours[i].first, theirs[i].first) << what << " at " << i;
    // Distinct positions: the pixel travels with its position.
    if ((i == 0 || theirs[i - 1].first != theirs[i].first) &&
        (i + 1 == theirs.size() || theirs[i + 1].first != theirs[i].first)) {
      EXPECT_EQ(ours[i].second, theirs[i].second) << what << " at " << i;
    }
  }
}

TEST(OrderStatisticsTest, SortByPositionSortsAsStdSort) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> along(-300, 300), jitter(-2, 2);
  for (int trial = 0; trial < 200; ++trial) {
    // A line's support: one pixel per step along it, in a scrambled order, some gaps.
    Support support;
    const double step = 0.5 + (rng() % 4) * 0.5;
    for (double t = along(rng); t < 300; t += step)
      if (rng() % 5 != 0)
        support.emplace_back(t + 0.1 * jitter(rng), Eigen::Vector2d(t, jitter(rng)));
    std::shuffle(support.begin(), support.end(), rng);
    ExpectSortedAsStd(support, "line " + std::to_string(trial));
  }
  // Sparse (std::sort's path), ties, non-finite, tiny.
  ExpectSortedAsStd({{0.0, {0, 0}}, {1e6, {1, 0}}, {-5e5, {2, 0}}}, "sparse");
  ExpectSortedAsStd({{3.0, {0, 0}}, {1.0, {1, 0}}, {3.0, {2, 0}}, {2.0, {3, 0}}}, "ties");
  ExpectSortedAsStd(
      {{3.0, {0, 0}}, {std::numeric_limits<double>::infinity(), {1, 0}}, {1.0, {2, 0}}},
      "infinite");
  ExpectSortedAsStd({{2.0, {0, 0}}}, "one");
  ExpectSortedAsStd({}, "none");
}

}  // namespace
}  // namespace monocle
