#include "service/vision/y_junctions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

// Whether three segments make a Y: their lines pass close to one point, each segment starts
// near it and runs away from it, and the three rays' angles are those of a ceiling corner
// seen from below (see FindYCandidates). The Y, scored by its edges' support, or nothing.
std::optional<YTriple> JudgeTriple(const std::vector<Segment>& segments,
                                   const std::array<int, 3>& index, int w, int h,
                                   double junction_radius) {
  const double min_angle = 80 * kPi / 180;
  const std::array<const Segment*, 3> s{&segments[index[0]], &segments[index[1]],
                                        &segments[index[2]]};
  // The corner: the point closest to all three lines. (Pairwise intersections slide
  // far along two nearly collinear edges, which a Y often has.)
  Eigen::Matrix2d normal_matrix = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const auto* seg : s) {
    normal_matrix += seg->normal * seg->normal.transpose();
    rhs += seg->rho * seg->normal;
  }
  if (std::abs(normal_matrix.determinant()) < 1e-6) return std::nullopt;
  const Eigen::Vector2d c = normal_matrix.inverse() * rhs;
  if (std::abs(s[0]->normal.dot(c) - s[0]->rho) > junction_radius ||
      std::abs(s[1]->normal.dot(c) - s[1]->rho) > junction_radius ||
      std::abs(s[2]->normal.dot(c) - s[2]->rho) > junction_radius) {
    return std::nullopt;
  }
  YTriple t;
  t.segment = index;
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
  if (!ok) return std::nullopt;
  const double a01 = AngleBetween(t.direction[0], t.direction[1]);
  const double a12 = AngleBetween(t.direction[1], t.direction[2]);
  const double a02 = AngleBetween(t.direction[0], t.direction[2]);
  if (a01 < min_angle || a12 < min_angle || a02 < min_angle) return std::nullopt;
  // A Y, not an arrow: the three angles around the corner add up to a full turn.
  if (std::abs(a01 + a12 + a02 - 2 * kPi) > 0.05) return std::nullopt;
  t.score = score;
  return t;
}

}  // namespace

double AngleBetween(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

std::vector<YTriple> FindYCandidates(const std::vector<Segment>& segments, int w, int h,
                                     double junction_radius) {
  std::vector<YTriple> found;
  const int n = static_cast<int>(segments.size());
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
        if (auto t = JudgeTriple(segments, {i, j, k}, w, h, junction_radius)) found.push_back(*t);
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

}  // namespace monocle::corner_detection
