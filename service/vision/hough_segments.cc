#include "service/vision/hough_segments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "service/vision/order_statistics.h"

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

// The peaks, most votes first, each once, without the near-duplicates of a stronger one
// (within 3 degrees and 6 px); at most `max_peaks`.
std::vector<HoughPeak> StrongestDistinct(std::vector<HoughPeak> peaks, int max_peaks) {
  // Most votes first; equal votes in cell order, so the result does not depend on the
  // order the candidates arose in.
  std::sort(peaks.begin(), peaks.end(), [](const HoughPeak& x, const HoughPeak& y) {
    return x.votes != y.votes ? x.votes > y.votes
                              : std::tie(x.angle_bin, x.rho_bin) < std::tie(y.angle_bin, y.rho_bin);
  });
  peaks.erase(std::unique(peaks.begin(), peaks.end(),
                          [](const HoughPeak& x, const HoughPeak& y) {
                            return x.angle_bin == y.angle_bin && x.rho_bin == y.rho_bin;
                          }),
              peaks.end());
  // Suppress near-duplicates of stronger peaks (within 3 degrees and 6 px).
  std::vector<HoughPeak> kept;
  for (const auto& p : peaks) {
    bool duplicate = false;
    for (const auto& k : kept) {
      int da = std::abs(p.angle_bin - k.angle_bin);
      int dr = std::abs(p.rho_bin - k.rho_bin);
      if (da > kAngleBins / 2) {  // across the wrap the same line has -rho
        da = kAngleBins - da;
        dr = std::abs(p.rho_bin + k.rho_bin);
      }
      if (da <= 6 && dr <= 6) duplicate = true;
    }
    if (!duplicate) kept.push_back(p);
    if (static_cast<int>(kept.size()) >= max_peaks) break;
  }
  return kept;
}

}  // namespace

std::vector<HoughPeak> HoughPeaks(const std::vector<EdgePixel>& edges, int w, int h, int min_votes,
                                  int max_peaks) {
  static const auto tables = [] {
    std::array<std::array<float, kAngleBins>, 2> t;
    for (int a = 0; a < kAngleBins; ++a) {
      t[0][a] = static_cast<float>(std::cos(a * kPi / kAngleBins));
      t[1][a] = static_cast<float>(std::sin(a * kPi / kAngleBins));
    }
    return t;
  }();
  const auto* cos_table = &tables[0];
  const auto* sin_table = &tables[1];
  const int d = static_cast<int>(std::ceil(std::hypot(w, h))) + 2;
  const int rho_bins = 2 * d + 1;
  // 16-bit counts (a line has far fewer than 65535 votes), kept per thread and left all
  // zero after each use: allocated per frame, its 0.7-1.5 MB came from fresh pages, whose
  // faults and zeroing cost more than all the votes. Cleared afterwards by voting again
  // (setting zeros) when there are few votes, by zeroing it all when there are many.
  thread_local std::vector<uint16_t> acc;
  acc.resize(std::max(acc.size(), static_cast<size_t>(kAngleBins) * rho_bins), 0);
  auto for_each_vote = [&](auto&& vote) {
    for (const auto& e : edges) {
      double alpha = e.angle;
      if (alpha < 0) alpha += kPi;
      const int a0 = static_cast<int>(std::lround(alpha / kPi * kAngleBins));
      // rho + d + 0.5 > 0 always, so truncation rounds (std::lround was a third of the time).
      const float x = e.x, y = e.y, offset = static_cast<float>(d) + 0.5f;
      for (int da = -e.vote_half_window; da <= e.vote_half_window; ++da) {
        int a = a0 + da;
        if (a < 0) a += kAngleBins;
        if (a >= kAngleBins) a -= kAngleBins;
        const float rho = x * (*cos_table)[a] + y * (*sin_table)[a];
        vote(static_cast<size_t>(a) * rho_bins + static_cast<int>(rho + offset));
      }
    }
  };
  const int candidate_votes = std::max(1, (min_votes + 2) / 3);
  std::vector<size_t> candidates;
  // A peak of H' >= min_votes needs a cell of H >= min_votes / 3 (rounded up): remember
  // those as they arise instead of scanning the whole accumulator afterwards.
  size_t votes = 0;
  for_each_vote([&](size_t cell) {
    ++votes;
    if (++acc[cell] == candidate_votes) candidates.push_back(cell);
  });
  auto smoothed = [&](int a, int r) {
    // a is within a bin of the range: wrapping in angle flips rho; close enough.
    if (a < 0) a += kAngleBins;
    if (a >= kAngleBins) a -= kAngleBins;
    if (r < 1 || r >= rho_bins - 1) return 0;
    const uint16_t* row = &acc[static_cast<size_t>(a) * rho_bins];
    return row[r - 1] + row[r] + row[r + 1];
  };
  std::vector<HoughPeak> peaks;
  for (size_t candidate : candidates) {
    // H' may peak at the cell or at its rho neighbours. (A cell next to two candidates is
    // looked at twice: cheaper than sorting the candidates to visit each once.) One division
    // per candidate: done per cell, the divisions and wrapping took a sixth of this loop.
    const int a = static_cast<int>(candidate / rho_bins);
    const int r_candidate = static_cast<int>(candidate - static_cast<size_t>(a) * rho_bins);
    const uint16_t* row = &acc[static_cast<size_t>(a) * rho_bins];
    for (int r = std::max(r_candidate - 1, 1); r <= std::min(r_candidate + 1, rho_bins - 2); ++r) {
      const int v = row[r - 1] + row[r] + row[r + 1];
      if (v < min_votes) continue;
      bool is_max = true;
      // Inside the accumulator the neighbours' rows are read directly; at its edges through
      // smoothed(), which wraps in angle and stops at the rho range.
      const bool interior = a >= 1 && a < kAngleBins - 1 && r >= 2 && r < rho_bins - 2;
      for (int da = -1; da <= 1 && is_max; ++da) {
        const uint16_t* near_row = row + static_cast<std::ptrdiff_t>(da) * rho_bins;
        for (int dr = -1; dr <= 1 && is_max; ++dr) {
          if (da == 0 && dr == 0) continue;
          const int rr = r + dr;
          const int n =
              interior ? near_row[rr - 1] + near_row[rr] + near_row[rr + 1] : smoothed(a + da, rr);
          // Ties broken towards the lower index so a plateau yields one peak.
          if (n > v || (n == v && (da < 0 || (da == 0 && dr < 0)))) is_max = false;
        }
      }
      if (is_max) peaks.push_back({a, r - d, v});
    }
  }
  // A vote costs about as much as zeroing 40 cells.
  const size_t cells = static_cast<size_t>(kAngleBins) * rho_bins;
  if (votes * 40 < cells) {
    for_each_vote([&](size_t cell) { acc[cell] = 0; });
  } else {
    std::fill(acc.begin(), acc.begin() + static_cast<std::ptrdiff_t>(cells), 0);
  }
  return StrongestDistinct(std::move(peaks), max_peaks);
}

void SegmentsOfLine(const std::vector<const EdgePixel*>& edges, int line, double alpha, double rho,
                    double min_length, std::vector<Segment>* out) {
  Eigen::Vector2d normal(std::cos(alpha), std::sin(alpha));
  const double cos_tol = std::cos(20 * kPi / 180);  // weak edges: noisy directions
  // The Hough cell is coarse (0.5 degree moves the end of a 500 px line by 2 px): gather a
  // wide band first, fit it, then keep what lies within 1.5 px of the fitted line.
  {
    constexpr double band = 3.0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    int count = 0;
    for (const EdgePixel* ep : edges) {
      const EdgePixel& e = *ep;
      const Eigen::Vector2d p(e.x, e.y);
      if (std::abs(normal.dot(p) - rho) > band) continue;
      if (std::abs(normal.x() * e.nx + normal.y() * e.ny) < cos_tol) continue;
      mean += p;
      scatter += p * p.transpose();
      ++count;
    }
    if (count >= 2) {
      mean /= count;
      scatter = scatter / count - mean * mean.transpose();
      const double angle = 0.5 * std::atan2(2 * scatter(0, 1), scatter(0, 0) - scatter(1, 1));
      normal = Eigen::Vector2d(-std::sin(angle), std::cos(angle));
      rho = normal.dot(mean);
    }
  }
  const Eigen::Vector2d direction(-normal.y(), normal.x());
  std::vector<std::pair<double, Eigen::Vector2d>> support;
  for (const EdgePixel* ep : edges) {
    const EdgePixel& e = *ep;
    const Eigen::Vector2d p(e.x, e.y);
    if (std::abs(normal.dot(p) - rho) > 1.5) continue;
    if (std::abs(normal.x() * e.nx + normal.y() * e.ny) < cos_tol) continue;
    support.emplace_back(direction.dot(p), p);
  }
  SortByPosition(&support);
  constexpr double kMaxGap = 8;  // half-resolution pixels
  size_t start = 0;
  for (size_t i = 1; i <= support.size(); ++i) {
    if (i < support.size() && support[i].first - support[i - 1].first <= kMaxGap) continue;
    const size_t count = i - start;
    if (count >= 2) {
      const double length = support[i - 1].first - support[start].first;
      if (length >= min_length && count >= 0.5 * length) {
        // Least squares line of the run (the paper's eq. 17 via the scatter matrix).
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        for (size_t k = start; k < i; ++k) mean += support[k].second;
        mean /= static_cast<double>(count);
        Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
        for (size_t k = start; k < i; ++k) {
          const Eigen::Vector2d q = support[k].second - mean;
          scatter += q * q.transpose();
        }
        const double angle = 0.5 * std::atan2(2 * scatter(0, 1), scatter(0, 0) - scatter(1, 1));
        Segment s;
        s.line = line;
        s.direction = Eigen::Vector2d(std::cos(angle), std::sin(angle));
        s.normal = Eigen::Vector2d(-s.direction.y(), s.direction.x());
        s.rho = s.normal.dot(mean);
        double t0 = 1e9, t1 = -1e9;
        for (size_t k = start; k < i; ++k) {
          const double t = s.direction.dot(support[k].second);
          t0 = std::min(t0, t);
          t1 = std::max(t1, t);
        }
        s.t0 = t0;
        s.t1 = t1;
        s.support = static_cast<int>(count);
        out->push_back(s);
      }
    }
    start = i;
  }
}

}  // namespace monocle::corner_detection
