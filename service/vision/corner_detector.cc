#include "service/vision/corner_detector.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace monocle {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAngleBins = 360;     // 0.5 degree
constexpr int kVoteHalfWindow = 4;  // +-2 degrees around the gradient's direction

struct EdgePixel {
  float x, y;    // half-resolution pixel
  float nx, ny;  // unit gradient
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

// Sobel, then non-maximum suppression across the edge: the thinning step.
std::vector<EdgePixel> ThinEdges(const cv::Mat& img, double threshold) {
  cv::Mat gx, gy;
  cv::Sobel(img, gx, CV_16S, 1, 0, 3);
  cv::Sobel(img, gy, CV_16S, 0, 1, 3);
  const int w = img.cols, h = img.rows;
  cv::Mat mag(h, w, CV_32S);
  for (int y = 0; y < h; ++y) {
    const auto* px = gx.ptr<int16_t>(y);
    const auto* py = gy.ptr<int16_t>(y);
    auto* m = mag.ptr<int32_t>(y);
    for (int x = 0; x < w; ++x) m[x] = px[x] * px[x] + py[x] * py[x];
  }
  const int32_t t2 = static_cast<int32_t>(threshold * threshold);
  std::vector<EdgePixel> out;
  for (int y = 1; y < h - 1; ++y) {
    const auto* px = gx.ptr<int16_t>(y);
    const auto* py = gy.ptr<int16_t>(y);
    const auto* m = mag.ptr<int32_t>(y);
    const auto* up = mag.ptr<int32_t>(y - 1);
    const auto* down = mag.ptr<int32_t>(y + 1);
    for (int x = 1; x < w - 1; ++x) {
      const int32_t v = m[x];
      if (v < t2) continue;
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
      out.push_back({static_cast<float>(x), static_cast<float>(y), px[x] / norm, py[x] / norm});
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
    std::array<std::array<double, kAngleBins>, 2> t;
    for (int a = 0; a < kAngleBins; ++a) {
      t[0][a] = std::cos(a * kPi / kAngleBins);
      t[1][a] = std::sin(a * kPi / kAngleBins);
    }
    return t;
  }();
  const auto* cos_table = &tables[0];
  const auto* sin_table = &tables[1];
  const int d = static_cast<int>(std::ceil(std::hypot(w, h))) + 2;
  const int rho_bins = 2 * d + 1;
  // 16-bit counts: half the memory to clear each frame; a line has far fewer than 65535 votes.
  std::vector<uint16_t> acc(static_cast<size_t>(kAngleBins) * rho_bins, 0);
  const int candidate_votes = std::max(1, min_votes / 3);
  std::vector<size_t> candidates;
  for (const auto& e : edges) {
    double alpha = std::atan2(e.ny, e.nx);
    if (alpha < 0) alpha += kPi;
    const int a0 = static_cast<int>(std::lround(alpha / kPi * kAngleBins));
    for (int da = -kVoteHalfWindow; da <= kVoteHalfWindow; ++da) {
      const int a = ((a0 + da) % kAngleBins + kAngleBins) % kAngleBins;
      const double rho = e.x * (*cos_table)[a] + e.y * (*sin_table)[a];
      const size_t cell =
          static_cast<size_t>(a) * rho_bins + static_cast<int>(std::lround(rho)) + d;
      // A peak of H' >= min_votes needs a cell of H >= min_votes / 3: remember those as they
      // arise instead of scanning the whole accumulator afterwards.
      if (++acc[cell] == candidate_votes) candidates.push_back(cell);
    }
  }
  auto smoothed = [&](int a, int r) {
    a = (a % kAngleBins + kAngleBins) % kAngleBins;  // wrapping in angle flips rho; close enough
    if (r < 1 || r >= rho_bins - 1) return 0;
    const uint16_t* row = &acc[static_cast<size_t>(a) * rho_bins];
    return row[r - 1] + row[r] + row[r + 1];
  };
  std::vector<HoughPeak> peaks;
  std::vector<size_t> cells;
  for (size_t cell : candidates) {
    // H' may peak at the cell or at its rho neighbours.
    for (int dr = -1; dr <= 1; ++dr) cells.push_back(cell + dr);
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (size_t cell : cells) {
    const int a = static_cast<int>(cell / rho_bins), r = static_cast<int>(cell % rho_bins);
    if (r < 1 || r >= rho_bins - 1) continue;
    const int v = smoothed(a, r);
    if (v < min_votes) continue;
    bool is_max = true;
    for (int da = -1; da <= 1 && is_max; ++da) {
      for (int dr = -1; dr <= 1 && is_max; ++dr) {
        if (da == 0 && dr == 0) continue;
        const int n = smoothed(a + da, r + dr);
        // Ties broken towards the lower index so a plateau yields one peak.
        if (n > v || (n == v && (da < 0 || (da == 0 && dr < 0)))) is_max = false;
      }
    }
    if (is_max) peaks.push_back({a, r - d, v});
  }
  std::sort(peaks.begin(), peaks.end(),
            [](const HoughPeak& x, const HoughPeak& y) { return x.votes > y.votes; });
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
  const double cos_tol = std::cos(12 * kPi / 180);
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
  std::sort(support.begin(), support.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
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
// most supported wins; edges that run to the image border (the paper's check 3) count extra.
std::optional<YTriple> FindY(const std::vector<Segment>& segments, int w, int h,
                             double junction_radius) {
  YTriple best;
  const int n = static_cast<int>(segments.size());
  const double min_angle = 80 * kPi / 180;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (segments[j].line == segments[i].line) continue;
      for (int k = j + 1; k < n; ++k) {
        if (segments[k].line == segments[i].line || segments[k].line == segments[j].line) continue;
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
          const double ahead = s[m]->t1 - tc, behind = tc - s[m]->t0;
          const bool forward = ahead >= behind;
          const double overshoot = forward ? behind : ahead;
          const double length = s[m]->t1 - s[m]->t0;
          const double near = std::min(std::abs(s[m]->t0 - tc), std::abs(s[m]->t1 - tc));
          if (overshoot > std::max(1.5 * junction_radius, 0.15 * length) ||
              near > 4 * junction_radius)
            ok = false;
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
        if (t.score > best.score) best = t;
      }
    }
  }
  if (best.score < 0) return std::nullopt;
  return best;
}

float Bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const uint8_t* r0 = img.ptr<uint8_t>(y0);
  const uint8_t* r1 = img.ptr<uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

}  // namespace

std::vector<Eigen::Vector2d> MeasureEdgePoints(const cv::Mat& grey,
                                               const std::vector<Eigen::Vector2d>& positions,
                                               const std::vector<Eigen::Vector2d>& normals,
                                               double half_width_px, int polarity,
                                               double min_step_grey) {
  std::vector<Eigen::Vector2d> out;
  const int r = static_cast<int>(std::ceil(half_width_px)) + 1;
  std::vector<float> profile(2 * r + 1), deriv(2 * r + 1);
  for (size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector2d& p = positions[i];
    const Eigen::Vector2d& n = normals[i];
    const Eigen::Vector2d lo = p - (r + 1) * n.cwiseAbs(), hi = p + (r + 1) * n.cwiseAbs();
    if (std::min(lo.x(), p.x() - r - 1) < 0 || std::min(lo.y(), p.y() - r - 1) < 0 ||
        std::max(hi.x(), p.x() + r + 1) > grey.cols - 2 ||
        std::max(hi.y(), p.y() + r + 1) > grey.rows - 2) {
      continue;
    }
    for (int o = -r; o <= r; ++o) {
      const Eigen::Vector2d q = p + o * n;
      profile[o + r] = Bilinear(grey, q.x(), q.y());
    }
    int best = -1;
    float best_value = 0;
    for (int o = 1; o < 2 * r; ++o) {
      deriv[o] = polarity * 0.5f * (profile[o + 1] - profile[o - 1]);
      if (deriv[o] > best_value) {
        best_value = deriv[o];
        best = o;
      }
    }
    // A step of height s gives a derivative peak near s / 2 per pixel of blur; require a
    // clear maximum inside the window.
    if (best <= 1 || best >= 2 * r - 1 || best_value < 0.5 * min_step_grey) continue;
    const double left = deriv[best - 1], mid = deriv[best], right = deriv[best + 1];
    const double denom = left - 2 * mid + right;
    const double offset = denom < 0 ? 0.5 * (left - right) / denom : 0.0;
    if (std::abs(best - r + offset) > half_width_px) continue;
    out.push_back(p + (best - r + offset) * n);
  }
  return out;
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

// Pixel <-> undistorted pixel (the same camera without lens distortion).
Eigen::Vector2d UndistortPixel(const CameraIntrinsics& k, const Eigen::Vector2d& px,
                               Eigen::Matrix2d* jacobian) {
  Eigen::Matrix2d j = Eigen::Matrix2d::Identity();
  const auto n = PixelToNormalized(k, px, &j);
  if (!n) return px;
  const Eigen::Vector2d f(k.fx, k.fy);
  if (jacobian != nullptr) *jacobian = f.asDiagonal() * j;
  return {k.fx * n->x() + k.cx, k.fy * n->y() + k.cy};
}

Eigen::Vector2d RedistortPixel(const CameraIntrinsics& k, const Eigen::Vector2d& undistorted_px) {
  return NormalizedToPixel(
      k, Eigen::Vector2d((undistorted_px.x() - k.cx) / k.fx, (undistorted_px.y() - k.cy) / k.fy));
}

SegmentStage FindSegments(const cv::Mat& grey, const CornerDetectorOptions& options,
                          const CameraIntrinsics* k) {
  SegmentStage out;
  // Half resolution for detection: four times fewer pixels, and the Hough cells grow with it.
  out.scale = std::min(grey.cols, grey.rows) >= 400 ? 0.5 : 1.0;
  out.small = grey;
  if (out.scale < 1) cv::resize(grey, out.small, cv::Size(), out.scale, out.scale, cv::INTER_AREA);
  auto edges = ThinEdges(out.small, options.edge_threshold);
  if (k != nullptr && k->HasDistortion()) {
    // Move every edge pixel (and its gradient) to where an undistorted camera sees it.
    for (auto& e : edges) {
      Eigen::Matrix2d j = Eigen::Matrix2d::Identity();
      const Eigen::Vector2d u =
          UndistortPixel(*k, ToFull(Eigen::Vector2d(e.x, e.y), out.scale), &j);
      const Eigen::Vector2d p = ToSmall(u, out.scale);
      const Eigen::Vector2d tangent = (j * Eigen::Vector2d(-e.ny, e.nx)).normalized();
      e.x = static_cast<float>(p.x());
      e.y = static_cast<float>(p.y());
      e.nx = static_cast<float>(tangent.y());
      e.ny = static_cast<float>(-tangent.x());
    }
  }
  const double min_length = options.min_edge_length_px * out.scale;
  // Undistorted points may leave the frame a little: size the accumulator for 1.25x.
  const auto peaks = HoughPeaks(edges, out.small.cols * 5 / 4, out.small.rows * 5 / 4,
                                static_cast<int>(min_length), options.max_lines);
  // Edges bucketed by gradient direction (1 degree, modulo 180): a line only looks at the
  // edges within the 12 degrees its support test accepts.
  std::array<std::vector<const EdgePixel*>, 180> buckets;
  for (const auto& e : edges) {
    double deg = std::atan2(e.ny, e.nx) * 180 / kPi;
    if (deg < 0) deg += 180;
    buckets[static_cast<int>(deg) % 180].push_back(&e);
  }
  std::vector<const EdgePixel*> nearby;
  for (size_t i = 0; i < peaks.size(); ++i) {
    const double alpha = peaks[i].angle_bin * kPi / kAngleBins;
    const int center = static_cast<int>(alpha * 180 / kPi);
    nearby.clear();
    for (int b = center - 13; b <= center + 13; ++b) {
      const auto& bucket = buckets[((b % 180) + 180) % 180];
      nearby.insert(nearby.end(), bucket.begin(), bucket.end());
    }
    SegmentsOfLine(nearby, static_cast<int>(i), alpha, peaks[i].rho_bin, min_length, &out.segments);
  }
  return out;
}

// Full-resolution pixel of the image from a half-resolution (possibly undistorted) point.
Eigen::Vector2d ToImage(const Eigen::Vector2d& p, double scale, const CameraIntrinsics* k) {
  const Eigen::Vector2d full = ToFull(p, scale);
  return k != nullptr && k->HasDistortion() ? RedistortPixel(*k, full) : full;
}

}  // namespace

std::vector<HoughSegment> DetectStraightEdges(const cv::Mat& grey,
                                              const CornerDetectorOptions& options,
                                              const CameraIntrinsics* k) {
  std::vector<HoughSegment> out;
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols < 64 || grey.rows < 64) return out;
  const auto stage = FindSegments(grey, options, k);
  for (const auto& s : stage.segments) {
    out.push_back(
        {ToImage(s.End(0), stage.scale, k), ToImage(s.End(1), stage.scale, k), s.support});
  }
  return out;
}

Result<CornerEdges> DetectCornerEdges(const cv::Mat& grey, const CornerDetectorOptions& options,
                                      const CameraIntrinsics* k) {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return MakeError(ErrorCode::kInvalidArgument, "corner detection needs an 8-bit grey image");
  }
  if (grey.cols < 64 || grey.rows < 64) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "the image is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         ": too small to find a corner in (at least 64x64)");
  }
  const auto stage = FindSegments(grey, options, k);
  const double scale = stage.scale;
  const auto& segments = stage.segments;
  auto to_full = [&](const Eigen::Vector2d& p) { return ToImage(p, scale, k); };
  CornerEdges out;
  for (const auto& s : segments)
    out.hough_segments.push_back({to_full(s.End(0)), to_full(s.End(1)), s.support});
  const auto y =
      FindY(segments, stage.small.cols, stage.small.rows, options.junction_radius_px * scale);
  if (!y) {
    return MakeError(ErrorCode::kNotFound,
                     "no ceiling corner found: no three edges meet in a Y (found " +
                         std::to_string(segments.size()) + " straight edges)");
  }
  out.corner_px = to_full(y->corner);

  // Subpixel edge points at full resolution along each ray, from just off the corner (where
  // the three edges blur into each other) to the image border.
  const double max_t = std::hypot(grey.cols, grey.rows);
  for (int m = 0; m < 3; ++m) {
    // The ray's direction in the image, where it leaves the corner.
    const Eigen::Vector2d d =
        (to_full(y->corner + 10 * y->direction[m]) - out.corner_px).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    out.direction[m] = d;
    std::vector<Eigen::Vector2d> positions, normals;
    for (double t = 8; t < max_t; t += 2) {
      const Eigen::Vector2d p = out.corner_px + t * d;
      if (p.x() < 0 || p.y() < 0 || p.x() > grey.cols - 1 || p.y() > grey.rows - 1) break;
      positions.push_back(p);
      normals.push_back(n);
    }
    // Polarity: the sign the derivative has on most of the first samples.
    int votes = 0;
    const size_t probe = std::min<size_t>(positions.size(), 40);
    const std::vector<Eigen::Vector2d> first(positions.begin(), positions.begin() + probe);
    const std::vector<Eigen::Vector2d> first_normals(normals.begin(), normals.begin() + probe);
    votes += static_cast<int>(
        MeasureEdgePoints(grey, first, first_normals, 4, +1, options.min_step_grey).size());
    votes -= static_cast<int>(
        MeasureEdgePoints(grey, first, first_normals, 4, -1, options.min_step_grey).size());
    out.polarity[m] = votes >= 0 ? 1 : -1;
    out.points_px[m] =
        MeasureEdgePoints(grey, positions, normals, 4, out.polarity[m], options.min_step_grey);
    if (out.points_px[m].size() < 10) {
      return MakeError(ErrorCode::kNotFound, "a corner edge has too little contrast to measure");
    }
  }
  return out;
}

}  // namespace monocle
