#include "service/vision/corner_detector.h"

#include "service/geometry/undistortion_grid.h"
#include "service/vision/halve_image.h"
#include "service/vision/order_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <tuple>

namespace monocle {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAngleBins = 360;         // 0.5 degree
constexpr int kMinVoteHalfWindow = 4;   // +-2 degrees around the gradient's direction
constexpr int kMaxVoteHalfWindow = 20;  // +-10 degrees for the weakest edges

struct EdgePixel {
  float x, y;                // half-resolution pixel
  float nx, ny;              // unit gradient
  int vote_half_window = 4;  // Hough angle bins either side of the gradient's direction
  float angle = 0;           // atan2(ny, nx), radians: set once the gradient is final
};

// A line x cos(a) + y sin(a) = rho at half resolution, with the supporting span.
struct Segment {
  int line = 0;  // Hough peak it came from
  Eigen::Vector2d normal, direction;
  double rho = 0;
  double t0 = 0, t1 = 0;  // span along `direction`
  int support = 0;
  Eigen::Vector2d End(int i) const { return rho * normal + (i ? t1 : t0) * direction; }
};

// Four int32 lanes, compared all at once (GCC's vector extension).
using Lanes4 = int32_t __attribute__((vector_size(16)));

// Sobel, then non-maximum suppression across the edge: the thinning step. The threshold
// follows the image: in flat regions (most of a room) the gradient's two components are
// Gaussian noise, so its squared magnitude is exponential with median 2 ln 2 sigma_g^2.
// The threshold comes from a sample of pixels first (MedianOfNonNegative: the sample's
// nth_element was a third of this function's time), so the squared magnitudes are then
// computed three rows at a time, and only the pixels above it (a few in a hundred) are
// compared with their neighbours. The same edges, in the same order, as before.
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

struct HoughPeak {
  int angle_bin, rho_bin, votes;
};

// Hough transform in (alpha, rho), each edge voting only near its gradient's direction;
// peaks of the smoothed counts H'(a, r) = H(a, r - 1) + H(a, r) + H(a, r + 1).
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

// Splits the edge pixels supporting a Hough line into contiguous segments.
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

double AngleBetween(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

struct YTriple {
  std::array<int, 3> segment{};
  Eigen::Vector2d corner;
  std::array<Eigen::Vector2d, 3> direction;
  double score = -1;
};

// The paper's identification of the corner lines: the three lines passing close to one
// point (the paper asks the pairwise intersections to be close together), each segment ending near
// them and running away from them, and every angle between the three rays above 90 degrees (we
// allow 80 for lens distortion and the half-resolution Hough). Among the triples that pass, the
// most supported comes first; edges that run to the image border (the paper's check 3) count extra.
std::vector<YTriple> FindYCandidates(const std::vector<Segment>& segments, int w, int h,
                                     double junction_radius) {
  std::vector<YTriple> found;
  const int n = static_cast<int>(segments.size());
  const double min_angle = 80 * kPi / 180;
  // The checks below put an end of every segment within ~4.1 junction radii (or 0.3 of its
  // length) of the corner, so two segments of one Y have ends within 8.5 radii plus 0.3 of
  // their lengths of each other: pairs that do not are never looked at again (this prunes
  // the n^3 search to a few triples).
  // Each segment's partners with a higher index, in increasing order, and the same as a
  // flat n x n table.
  std::vector<std::array<Eigen::Vector2d, 2>> ends(n);
  for (int i = 0; i < n; ++i) ends[i] = {segments[i].End(0), segments[i].End(1)};
  std::vector<std::vector<int>> partners(n);
  std::vector<uint8_t> meets(static_cast<size_t>(n) * n, 0);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (segments[j].line == segments[i].line) continue;
      const double reach = 8.5 * junction_radius + 0.3 * (segments[i].t1 - segments[i].t0 +
                                                          segments[j].t1 - segments[j].t0);
      double closest2 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          closest2 = std::min(closest2, (ends[i][a] - ends[j][b]).squaredNorm());
      if (closest2 <= reach * reach) {
        partners[i].push_back(j);
        meets[static_cast<size_t>(i) * n + j] = 1;
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    for (const int j : partners[i]) {
      for (const int k : partners[j]) {  // k > j meets j; it must meet i too
        if (!meets[static_cast<size_t>(i) * n + k]) continue;
        const std::array<const Segment*, 3> s{&segments[i], &segments[j], &segments[k]};
        // The corner: the point closest to all three lines. (Pairwise intersections slide
        // far along two nearly collinear edges, which a Y often has.)
        Eigen::Matrix2d normal_matrix = Eigen::Matrix2d::Zero();
        Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
        for (const auto* seg : s) {
          normal_matrix += seg->normal * seg->normal.transpose();
          rhs += seg->rho * seg->normal;
        }
        if (std::abs(normal_matrix.determinant()) < 1e-6) continue;
        const Eigen::Vector2d c = normal_matrix.inverse() * rhs;
        if (std::abs(s[0]->normal.dot(c) - s[0]->rho) > junction_radius ||
            std::abs(s[1]->normal.dot(c) - s[1]->rho) > junction_radius ||
            std::abs(s[2]->normal.dot(c) - s[2]->rho) > junction_radius) {
          continue;
        }
        YTriple t;
        t.segment = {i, j, k};
        t.corner = c;
        bool ok = true;
        double score = 0;
        for (int m = 0; m < 3 && ok; ++m) {
          const double tc = s[m]->direction.dot(c);
          // The segment must lie on one side of the corner and start near it. It may run a
          // little past the corner: two nearly collinear edges support each other there.
          const double forward_part = s[m]->t1 - tc, backward_part = tc - s[m]->t0;
          const bool forward = forward_part >= backward_part;
          const double ahead = std::max(forward_part, backward_part);
          const double behind = std::min(forward_part, backward_part);
          const double overshoot = behind;
          const double length = s[m]->t1 - s[m]->t0;
          const double near = std::min(std::abs(s[m]->t0 - tc), std::abs(s[m]->t1 - tc));
          // Its pixels past the corner may belong to a nearly collinear edge of the triple
          // (within 20 degrees of straight on): then up to half its length ahead.
          bool collinear_partner = false;
          for (int o = 0; o < 3; ++o) {
            if (o != m && std::abs(s[o]->direction.dot(s[m]->direction)) > std::cos(kPi / 9))
              collinear_partner = true;
          }
          const double allowed = collinear_partner ? std::max(1.5 * junction_radius, 0.5 * ahead)
                                                   : std::max(1.5 * junction_radius, 0.15 * length);
          // A segment may start up to 0.3 of its length from the corner: light and shading
          // can make two walls alike just there, so the wall-wall edge appears only further
          // down (then the floor corner at its other end was taken for the ceiling's).
          if (overshoot > allowed || near > std::max(4 * junction_radius, 0.3 * length)) ok = false;
          t.direction[m] = forward ? s[m]->direction : Eigen::Vector2d(-s[m]->direction);
          score += s[m]->support;
          const Eigen::Vector2d far = forward ? s[m]->End(1) : s[m]->End(0);
          if (far.x() < 8 || far.y() < 8 || far.x() > w - 9 || far.y() > h - 9)
            score += 0.25 * s[m]->support;
        }
        if (!ok) continue;
        const double a01 = AngleBetween(t.direction[0], t.direction[1]);
        const double a12 = AngleBetween(t.direction[1], t.direction[2]);
        const double a02 = AngleBetween(t.direction[0], t.direction[2]);
        if (a01 < min_angle || a12 < min_angle || a02 < min_angle) continue;
        // A Y, not an arrow: the three angles around the corner add up to a full turn.
        if (std::abs(a01 + a12 + a02 - 2 * kPi) > 0.05) continue;
        t.score = score;
        found.push_back(t);
      }
    }
  }
  std::sort(found.begin(), found.end(),
            [](const YTriple& a, const YTriple& b) { return a.score > b.score; });
  // Best first; the same Y from duplicate segments counts once.
  std::vector<YTriple> distinct;
  for (const auto& t : found) {
    bool seen = false;
    for (const auto& d : distinct) {
      bool same_rays = true;
      for (const auto& ray : t.direction) {
        bool matched = false;
        for (const auto& other : d.direction) matched |= ray.dot(other) > std::cos(kPi / 60);
        same_rays &= matched;
      }
      seen |= same_rays && (d.corner - t.corner).norm() < junction_radius;
    }
    if (!seen) distinct.push_back(t);
    if (distinct.size() >= 10) break;
  }
  return distinct;
}

std::string FormatGrey(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

}  // namespace

double MinStepGrey(const CornerDetectorOptions& options, double noise_sigma_grey) {
  return std::max(options.min_step_grey, options.min_step_snr * noise_sigma_grey);
}

namespace {

struct SegmentStage {
  double scale = 1;
  cv::Mat small;
  std::vector<Segment> segments;
};

Eigen::Vector2d ToFull(const Eigen::Vector2d& p, double scale) {
  return ((p.array() + 0.5) / scale - 0.5).matrix();
}
Eigen::Vector2d ToSmall(const Eigen::Vector2d& p, double scale) {
  return ((p.array() + 0.5) * scale - 0.5).matrix();
}

// Undistorted pixel (the same camera without lens distortion) -> pixel.
Eigen::Vector2d RedistortPixel(const CameraIntrinsics& k, const Eigen::Vector2d& undistorted_px) {
  return NormalizedToPixel(
      k, Eigen::Vector2d((undistorted_px.x() - k.cx) / k.fx, (undistorted_px.y() - k.cy) / k.fy));
}

// The frame at the detection scales, halved once per frame and shared by the searches at
// both scales. Halving twice (2x2 means, as INTER_AREA gives them; HalveImage) is ten times
// faster than one resize to a quarter (OpenCV's general area path).
class ScaledFrames {
 public:
  explicit ScaledFrames(const cv::Mat& grey) : full_(grey) {}
  const cv::Mat& At(double scale) {
    if (scale > 0.75) return full_;
    if (half_.empty()) HalveImage(full_, &half_);
    if (scale > 0.375) return half_;
    if (quarter_.empty()) HalveImage(half_, &quarter_);
    return quarter_;
  }

 private:
  cv::Mat full_, half_, quarter_;
};

SegmentStage FindSegments(ScaledFrames& frames, const CornerDetectorOptions& options,
                          const CameraIntrinsics* k, double scale) {
  SegmentStage out;
  out.scale = scale;
  out.small = frames.At(scale);
  // A Gaussian before the gradient: edges between alike-painted surfaces are a few grey
  // levels high, and smoothing over ~2 px raises a long edge's gradient above the noise
  // (the paper's Sobel alone is not enough at a contrast-to-noise of 2).
  cv::Mat smooth;
  cv::GaussianBlur(out.small, smooth, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REPLICATE);
  auto edges = ThinEdges(smooth, options);
  if (k != nullptr && k->HasDistortion()) {
    // Move every edge pixel (and its gradient) to where an undistorted camera sees it,
    // interpolated from a grid built once per camera (and thread).
    const UndistortionGrid& grid = UndistortionGridFor(*k);
    for (auto& e : edges) {
      Eigen::Matrix2d j;
      const Eigen::Vector2d u = grid.Undistort(ToFull(Eigen::Vector2d(e.x, e.y), out.scale), &j);
      const Eigen::Vector2d p = ToSmall(u, out.scale);
      const Eigen::Vector2d tangent = (j * Eigen::Vector2d(-e.ny, e.nx)).normalized();
      e.x = static_cast<float>(p.x());
      e.y = static_cast<float>(p.y());
      e.nx = static_cast<float>(tangent.y());
      e.ny = static_cast<float>(-tangent.x());
    }
  }
  for (auto& e : edges) e.angle = std::atan2(e.ny, e.nx);  // used by the Hough and the buckets
  const double min_length = options.min_edge_length_px * out.scale;
  // Undistorted points may leave the frame a little: size the accumulator for 1.25x. A peak
  // needs 70 % of the shortest edge's pixels (the ends and the junction blur away); the
  // segment itself must still be that long.
  const auto peaks = HoughPeaks(edges, out.small.cols * 5 / 4, out.small.rows * 5 / 4,
                                static_cast<int>(0.7 * min_length), options.max_lines);
  // Edges bucketed by gradient direction (1 degree, modulo 180): a line only looks at the
  // edges within the 20 degrees its support test accepts.
  std::array<std::vector<const EdgePixel*>, 180> buckets;
  for (const auto& e : edges) {
    double deg = e.angle * 180 / kPi;
    if (deg < 0) deg += 180;
    buckets[static_cast<int>(deg) % 180].push_back(&e);
  }
  std::vector<const EdgePixel*> nearby;
  for (size_t i = 0; i < peaks.size(); ++i) {
    const double alpha = peaks[i].angle_bin * kPi / kAngleBins;
    const int center = static_cast<int>(alpha * 180 / kPi);
    nearby.clear();
    for (int b = center - 21; b <= center + 21; ++b) {
      const auto& bucket = buckets[((b % 180) + 180) % 180];
      nearby.insert(nearby.end(), bucket.begin(), bucket.end());
    }
    SegmentsOfLine(nearby, static_cast<int>(i), alpha, peaks[i].rho_bin, min_length, &out.segments);
  }
  // Several peaks of one wide Hough ridge refit to the same segment: keep one.
  std::vector<Segment> distinct;
  for (const auto& seg : out.segments) {
    bool seen = false;
    for (const auto& d : distinct) {
      seen |= (((seg.End(0) - d.End(0)).norm() < 2 && (seg.End(1) - d.End(1)).norm() < 2) ||
               ((seg.End(0) - d.End(1)).norm() < 2 && (seg.End(1) - d.End(0)).norm() < 2));
    }
    if (!seen) distinct.push_back(seg);
  }
  out.segments = std::move(distinct);
  return out;
}

// Full-resolution pixel of the image from a half-resolution (possibly undistorted) point.
Eigen::Vector2d ToImage(const Eigen::Vector2d& p, double scale, const CameraIntrinsics* k) {
  const Eigen::Vector2d full = ToFull(p, scale);
  return k != nullptr && k->HasDistortion() ? RedistortPixel(*k, full) : full;
}

// Whether the image is clipped (3x3 mean >= 250, or <= 5) on either side of an edge through
// `p` (full-resolution pixel, `normal` across the edge), 4 px off it: the edge cannot be
// measured there (PeakOfProfile leaves such points out) nor its contrast be judged.
bool ClippedAcross(const cv::Mat& grey, const Eigen::Vector2d& p, const Eigen::Vector2d& normal) {
  auto mean3x3 = [&](const Eigen::Vector2d& q) {
    const int x = static_cast<int>(std::lround(q.x())), y = static_cast<int>(std::lround(q.y()));
    if (x < 1 || y < 1 || x > grey.cols - 2 || y > grey.rows - 2) return -1;
    int sum = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      const uint8_t* row = grey.ptr<uint8_t>(y + dy);
      sum += row[x - 1] + row[x] + row[x + 1];
    }
    return sum / 9;
  };
  const int a = mean3x3(p + 4 * normal), b = mean3x3(p - 4 * normal);
  if (a < 0 || b < 0) return false;
  return std::max(a, b) >= 250 || std::min(a, b) <= 5;
}

// Whether at least 80 % of the points every 8 px from `from` to `to` (full-resolution
// pixels) are ClippedAcross the line between them.
bool ClippedAlong(const cv::Mat& grey, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const double length = (to - from).norm();
  if (length < 1) return false;
  const Eigen::Vector2d d = (to - from) / length;
  const Eigen::Vector2d normal(-d.y(), d.x());
  const int n = std::max(2, static_cast<int>(length / 8));
  int clipped = 0;
  for (int i = 0; i < n; ++i)
    clipped += ClippedAcross(grey, from + (i + 0.5) * length / n * d, normal);
  return 5 * clipped >= 4 * n;
}

// Edge points from the corner outwards to the image border: measured in chunks of 32 px
// along the current line, which is refitted to the points found so far (the last 300 px of
// them) before the next chunk. A Hough direction from a short segment near the corner is a
// degree off; a straight ray would leave a long edge long before the border, and lens
// distortion bends the edge away from any straight ray.
std::vector<EdgePointSample> TraceEdge(const cv::Mat& grey, const Eigen::Vector2d& corner,
                                       Eigen::Vector2d direction, double min_step, int spacing_px) {
  const int spacing = std::max(spacing_px, 1);
  constexpr double kChunk = 32, kMemory = 300;
  std::vector<EdgePointSample> found;
  Eigen::Vector2d origin = corner;  // the current line passes here along `direction`
  double t = 8;                     // distance along the line from `origin`
  int misses = 0;                   // chunks in a row without a point
  // A long gap (contrast fading where shading evens the two surfaces out) is crossed on the
  // last line; the trace ends at the border or after 8 empty chunks not clipped.
  std::vector<Eigen::Vector2d> positions;
  while (misses < 8) {
    positions.clear();
    bool inside = true;
    for (double s = 0; s < kChunk; s += spacing, t += spacing) {
      const Eigen::Vector2d p = origin + t * direction;
      if (p.x() < 0 || p.y() < 0 || p.x() > grey.cols - 1 || p.y() > grey.rows - 1) {
        inside = false;
        break;
      }
      positions.push_back(p);
    }
    const auto chunk = positions.empty()
                           ? std::vector<EdgePointSample>{}
                           : MajoritySign(MeasureEdgeStretch(grey, positions.front(), direction,
                                                             static_cast<int>(positions.size()),
                                                             spacing, 4, 0, min_step));
    // An empty chunk where the image is clipped beside the line is no evidence that the edge
    // ended: a lamp's glare whitens the walls near the ceiling, and no point can be measured
    // beside a clipped side, but the edge shows again beyond the glare.
    if (!chunk.empty())
      misses = 0;
    else if (positions.empty() ||
             !ClippedAlong(grey, positions.front(), positions.back() + direction))
      ++misses;
    found.insert(found.end(), chunk.begin(), chunk.end());
    if (!inside) break;
    // Refit on the recent points (within kMemory of the line's end): total least squares,
    // in two passes over the points rather than a copy of them.
    const Eigen::Vector2d last = origin + t * direction;
    auto recent = [&](const EdgePointSample& f) {
      return (f.point_px - last).squaredNorm() < kMemory * kMemory;
    };
    size_t count = 0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& f : found) {
      if (!recent(f)) continue;
      mean += f.point_px;
      ++count;
    }
    if (count < 8) continue;
    mean /= static_cast<double>(count);
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& f : found) {
      if (recent(f)) scatter += (f.point_px - mean) * (f.point_px - mean).transpose();
    }
    const double angle = 0.5 * std::atan2(2 * scatter(0, 1), scatter(0, 0) - scatter(1, 1));
    Eigen::Vector2d fitted(std::cos(angle), std::sin(angle));
    if (fitted.dot(direction) < 0) fitted = -fitted;
    if (fitted.dot(direction) < std::cos(10 * kPi / 180)) continue;  // noise, not the edge
    direction = fitted;
    origin = mean;
    t = direction.dot(last - mean);
  }
  return found;
}

// Whether a quarter or more of the pixels within 40 px of `center` are clipped (>= 250 or
// <= 5): edge points beside such surfaces are not measured (see edge_profile.cc).
bool SaturatedAround(const cv::Mat& grey, const Eigen::Vector2d& center) {
  const cv::Rect box =
      cv::Rect(static_cast<int>(center.x()) - 40, static_cast<int>(center.y()) - 40, 81, 81) &
      cv::Rect(0, 0, grey.cols, grey.rows);
  if (box.area() == 0) return false;
  int clipped = 0;
  for (int y = box.y; y < box.y + box.height; ++y) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    for (int x = box.x; x < box.x + box.width; ++x) clipped += row[x] >= 250 || row[x] <= 5;
  }
  return 4 * clipped >= box.area();
}

// Subpixel edge points at full resolution along each edge of one Y, from just off the corner
// (where the three edges blur into each other) to the image border.
template <typename ToFull>
Result<CornerEdges> MeasureY(const cv::Mat& grey, const YTriple& y, int spacing_px, CornerEdges out,
                             const ToFull& to_full, double min_step) {
  out.corner_px = to_full(y.corner);
  out.sample_spacing_px = spacing_px;
  for (int m = 0; m < 3; ++m) {
    // The ray's direction in the image, where it leaves the corner.
    const Eigen::Vector2d d =
        (to_full(y.corner + 10 * y.direction[m]) - out.corner_px).normalized();
    out.direction[m] = d;
    out.points_px[m].clear();
    out.step_grey[m].clear();
    const auto samples = TraceEdge(grey, out.corner_px, d, min_step, spacing_px);
    for (const auto& sample : samples) {
      out.points_px[m].push_back(sample.point_px);
      out.step_grey[m].push_back(sample.step_grey);
    }
    out.blur_sigma_px[m] = EdgeBlurSigmaPx(samples);
    // Polarity: the sign most points near the corner have.
    int votes = 0;
    for (size_t i = 0;
         i < out.points_px[m].size() && static_cast<int>(i) < 80 / std::max(spacing_px, 1); ++i)
      votes += out.step_grey[m][i] > 0 ? 1 : -1;
    out.polarity[m] = votes >= 0 ? 1 : -1;
    // Fewer points than 20 px of edge hold.
    if (static_cast<int>(out.points_px[m].size()) * spacing_px < 20) {
      if (SaturatedAround(grey, out.corner_px)) {
        return MakeError(ErrorCode::kNotFound,
                         "a corner edge cannot be measured: the surfaces around the corner are "
                         "saturated (white or black clipped); lower the exposure or gain");
      }
      // Glare along the edge rather than around the corner: no point is measured beside a
      // clipped side, however clear the edge looks.
      if (ClippedAlong(grey, out.corner_px + 8 * d, out.corner_px + 200 * d)) {
        return MakeError(ErrorCode::kNotFound,
                         "a corner edge cannot be measured: a surface beside it is saturated "
                         "(white or black clipped) over most of its first 200 px; lower the "
                         "exposure or gain");
      }
      return MakeError(ErrorCode::kNotFound, "a corner edge has too little contrast to measure (" +
                                                 std::to_string(out.points_px[m].size()) +
                                                 " points with a step of at least " +
                                                 FormatGrey(min_step) + " grey levels at noise " +
                                                 FormatGrey(out.measurement_noise_grey) + ")");
    }
  }
  return out;
}

// Why no Y was found, in the user's terms: how many edges, whether two of them meet, and
// how strong the strongest third edge leaving their junction is against the noise.
std::string DiagnoseMissingY(const cv::Mat& grey, const std::vector<Segment>& segments,
                             double scale, const CameraIntrinsics* k, double noise_sigma,
                             double junction_radius) {
  // Distinct lines (segments of one Hough line count once).
  std::vector<const Segment*> distinct;
  for (const auto& s : segments) {
    bool seen = false;
    for (const auto* d : distinct)
      seen |= std::abs(d->direction.dot(s.direction)) > std::cos(kPi / 60) &&
              std::abs(d->rho - s.normal.dot(d->normal) * s.rho) < 3;
    if (!seen) distinct.push_back(&s);
  }
  const std::string edges = std::to_string(distinct.size()) + " straight edge" +
                            (distinct.size() == 1 ? "" : "s") + " found";
  if (distinct.size() < 2) return edges + "; a corner needs three meeting in a Y";
  // The best supported pair whose segments end near their lines' intersection.
  double best_support = -1;
  Eigen::Vector2d junction = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 2> rays{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY()};
  for (size_t i = 0; i < distinct.size(); ++i) {
    for (size_t j = i + 1; j < distinct.size(); ++j) {
      const Segment& a = *distinct[i];
      const Segment& b = *distinct[j];
      Eigen::Matrix2d m;
      m << a.normal.transpose(), b.normal.transpose();
      if (std::abs(m.determinant()) < 0.2) continue;  // nearly parallel
      const Eigen::Vector2d c = m.inverse() * Eigen::Vector2d(a.rho, b.rho);
      auto end_near = [&](const Segment& s, Eigen::Vector2d* ray) {
        const double tc = s.direction.dot(c);
        const double d0 = std::abs(s.t0 - tc), d1 = std::abs(s.t1 - tc);
        *ray = d0 < d1 ? s.direction : Eigen::Vector2d(-s.direction);
        return std::min(d0, d1) < 4 * junction_radius;
      };
      std::array<Eigen::Vector2d, 2> r{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY()};
      if (!end_near(a, &r[0]) || !end_near(b, &r[1])) continue;
      if (a.support + b.support > best_support) {
        best_support = a.support + b.support;
        junction = c;
        rays = r;
      }
    }
  }
  if (best_support < 0) return edges + ", but no two of them meet at a corner";
  // Around the junction, the strongest straight step in any other direction.
  const Eigen::Vector2d corner = ToImage(junction, scale, k);
  double strongest = 0;
  for (int deg = 0; deg < 360; deg += 3) {
    const Eigen::Vector2d d(std::cos(deg * kPi / 180), std::sin(deg * kPi / 180));
    if (d.dot(rays[0]) > std::cos(kPi / 9) || d.dot(rays[1]) > std::cos(kPi / 9)) continue;
    std::vector<Eigen::Vector2d> positions, normals;
    for (double t = 10; t < 130; t += 2) {
      positions.push_back(corner + t * d);
      normals.emplace_back(-d.y(), d.x());
    }
    for (int sign : {+1, -1}) {
      const auto found = MeasureEdgePoints(grey, positions, normals, 3, sign, 0.5);
      if (found.size() < positions.size() / 2) continue;
      std::vector<double> steps;
      for (const auto& f : found) steps.push_back(std::abs(f.step_grey));
      std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
      strongest = std::max(strongest, steps[steps.size() / 2]);
    }
  }
  char where[64];
  std::snprintf(where, sizeof where, " at (%.0f, %.0f) px", corner.x(), corner.y());
  const std::string measured =
      "contrast " + FormatGrey(strongest) + " grey levels at noise " + FormatGrey(noise_sigma);
  // A step well above the noise that still is no edge of a Y: clutter or a curved shade.
  if (strongest > 4 * std::max(noise_sigma, 0.5))
    return edges + "; 2 meet" + where + " but no straight third edge leaves it (strongest step " +
           measured + ")";
  // No third edge where the walls around the junction are clipped white: the glare hides it.
  if (SaturatedAround(grey, corner))
    return edges + "; 2 meet" + where +
           " but the surfaces around them are saturated (white or black clipped), which hides "
           "the third; lower the exposure or gain";
  return edges + "; 2 meet" + where + " but the third is too weak (" + measured + ")";
}

// One detection at `scale` of the image: the Hough stage there, then every Y it finds
// measured at full resolution and offered to `accept`. Nothing, or why none was accepted;
// with `diagnose`, a view without a Y says what was seen (measured at full resolution: a
// twentieth of a detection, spent only where the reason is reported).
std::optional<Error> TryScale(const cv::Mat& grey, ScaledFrames& frames,
                              const CornerDetectorOptions& options, const CameraIntrinsics* k,
                              double scale, double noise_sigma_grey, double measurement_noise_grey,
                              bool diagnose, const std::function<bool(CornerEdges)>& accept) {
  const auto stage = FindSegments(frames, options, k, scale);
  const auto& segments = stage.segments;
  auto to_full = [&](const Eigen::Vector2d& p) { return ToImage(p, scale, k); };
  CornerEdges out;
  out.direction.fill(Eigen::Vector2d::Zero());  // set per Y by MeasureY
  out.detection_scale = scale;
  for (const auto& s : segments)
    out.hough_segments.push_back({to_full(s.End(0)), to_full(s.End(1)), s.support});
  const auto candidates = FindYCandidates(segments, stage.small.cols, stage.small.rows,
                                          options.junction_radius_px * scale);
  out.noise_sigma_grey = noise_sigma_grey;
  out.measurement_noise_grey = measurement_noise_grey;
  const double min_step = MinStepGrey(options, out.noise_sigma_grey);
  if (candidates.empty() && !diagnose)
    return MakeError(ErrorCode::kNotFound, "no ceiling corner found at this resolution");
  if (candidates.empty()) {
    return MakeError(ErrorCode::kNotFound,
                     "no ceiling corner found: " +
                         DiagnoseMissingY(grey, segments, scale, k, out.measurement_noise_grey,
                                          options.junction_radius_px * scale));
  }
  // The best supported Y first; a Y whose edges cannot be measured at full resolution
  // (clutter or shading that looked like an edge at low resolution) is passed over.
  std::optional<Error> why;
  for (const auto& y : candidates) {
    auto edges = MeasureY(grey, y, options.trace_spacing_px, out, to_full, min_step);
    if (!edges) {
      if (!why) why = edges.error();
      continue;
    }
    if (accept(std::move(*edges))) return std::nullopt;
    if (!why) why = MakeError(ErrorCode::kNotFound, "no Y found is a ceiling corner");
  }
  return why;
}

// Detection's resolution: half for a camera image (a quarter of the pixels, and the Hough
// cells grow with it); with `first`, a quarter for images at least 800 px on each side,
// tried before half: its 4x4 averages quarter the noise, so long edges stand out as well,
// and a view whose short edge it misses is tried again at half.
double DetectionScale(const cv::Mat& grey, bool first) {
  const int side = std::min(grey.cols, grey.rows);
  if (first && side >= 800) return 0.25;
  return side >= 400 ? 0.5 : 1.0;
}

}  // namespace

std::vector<HoughSegment> DetectStraightEdges(const cv::Mat& grey,
                                              const CornerDetectorOptions& options,
                                              const CameraIntrinsics* k) {
  std::vector<HoughSegment> out;
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols < 64 || grey.rows < 64) return out;
  ScaledFrames frames(grey);
  const auto stage = FindSegments(frames, options, k, DetectionScale(grey, false));
  for (const auto& s : stage.segments) {
    out.push_back(
        {ToImage(s.End(0), stage.scale, k), ToImage(s.End(1), stage.scale, k), s.support});
  }
  return out;
}

Result<CornerEdges> DetectCornerEdges(const cv::Mat& grey, const CornerDetectorOptions& options,
                                      const CameraIntrinsics* k) {
  std::optional<CornerEdges> found;
  const auto error = ForEachCornerCandidate(grey, options, k, [&](CornerEdges edges) {
    found = std::move(edges);
    return true;
  });
  if (error) return *error;
  return std::move(*found);
}

std::optional<Error> ForEachCornerCandidate(const cv::Mat& grey,
                                            const CornerDetectorOptions& options,
                                            const CameraIntrinsics* k,
                                            const std::function<bool(CornerEdges)>& accept) {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return MakeError(ErrorCode::kInvalidArgument, "corner detection needs an 8-bit grey image");
  }
  if (grey.cols < 64 || grey.rows < 64) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "the image is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         ": too small to find a corner in (at least 64x64)");
  }
  const double coarse = DetectionScale(grey, options.quarter_resolution_first),
               fine = DetectionScale(grey, false);
  // Halved first: that reads the whole frame (from memory, for a camera's new frame), and
  // the noise estimate's rows are then read from the cache (a sixth less time for it).
  ScaledFrames frames(grey);
  frames.At(coarse);
  const double noise_sigma_grey = EstimateNoiseSigma(grey);
  const double measurement_noise_grey = EstimateMeasurementNoiseSigma(grey);
  const auto why = TryScale(grey, frames, options, k, coarse, noise_sigma_grey,
                            measurement_noise_grey, /*diagnose=*/coarse == fine, accept);
  if (!why || coarse == fine) return why;
  // Again at the finer resolution, whose reason is the one to report.
  return TryScale(grey, frames, options, k, fine, noise_sigma_grey, measurement_noise_grey,
                  /*diagnose=*/true, accept);
}

}  // namespace monocle
