#include "service/vision/edge_tracing.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

namespace monocle::corner_detection {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

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

}  // namespace monocle::corner_detection
