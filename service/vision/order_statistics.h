// Two selections the corner detector makes on every frame, done faster than the standard
// algorithms for the values it has, and with exactly their results (order_statistics_test
// compares them with std::nth_element and std::sort).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace monocle {

// The median (the upper one of an even count, as nth_element at size / 2 gives it) of
// non-negative values such as squared gradient magnitudes. Flat surfaces make most of them
// small, so it is usually found by counting them in 4096 bins, one per value, in a sixth of
// nth_element's time; beyond that, nth_element on the larger ones. `values` not empty.
int32_t MedianOfNonNegative(const std::vector<int32_t>& values);

// Sorts (position along a line, pixel) pairs by position, ascending: counted into 2 px bins,
// then insertion sort, which only moves a pair within its bin. A line's support is spread
// evenly along it, so this is linear; std::sort took half of the segment stage. Sparse or
// non-finite positions go to std::sort. Pairs with equal positions may come in either order,
// as with std::sort.
void SortByPosition(std::vector<std::pair<double, Eigen::Vector2d>>* support);

}  // namespace monocle
