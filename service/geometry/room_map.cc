#include "service/geometry/room_map.h"

#include <cmath>

namespace monocle {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Segments [a, b] and [c, d] share a point (touching counts).
bool SegmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  auto on_segment = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                       const Eigen::Vector2d& r) {  // r on [p, q], given collinear
    return std::min(p.x(), q.x()) - 1e-12 <= r.x() && r.x() <= std::max(p.x(), q.x()) + 1e-12 &&
           std::min(p.y(), q.y()) - 1e-12 <= r.y() && r.y() <= std::max(p.y(), q.y()) + 1e-12;
  };
  constexpr double kEps = 1e-12;
  if (((d1 > kEps && d2 < -kEps) || (d1 < -kEps && d2 > kEps)) &&
      ((d3 > kEps && d4 < -kEps) || (d3 < -kEps && d4 > kEps)))
    return true;
  if (std::abs(d1) <= kEps && on_segment(a, b, c)) return true;
  if (std::abs(d2) <= kEps && on_segment(a, b, d)) return true;
  if (std::abs(d3) <= kEps && on_segment(c, d, a)) return true;
  if (std::abs(d4) <= kEps && on_segment(c, d, b)) return true;
  return false;
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const MapCorner& c) {
  return os << "MapCorner{" << c.id << " in " << c.room_id << " at (" << c.position_m.x() << ", "
            << c.position_m.y() << ") m, X (" << c.x_edge.x() << ", " << c.x_edge.y() << "), Y ("
            << c.y_edge.x() << ", " << c.y_edge.y() << "), ceiling " << c.ceiling_height_m << " m}";
}

double SignedDoubleArea(const std::vector<Eigen::Vector2d>& outline) {
  double sum = 0;
  for (size_t i = 0; i < outline.size(); ++i)
    sum += Cross(outline[i], outline[(i + 1) % outline.size()]);
  return sum;
}

bool InsideOutline(const std::vector<Eigen::Vector2d>& outline, const Eigen::Vector2d& p,
                   double margin_m) {
  const size_t n = outline.size();
  if (n < 3) return false;
  bool inside = false;  // even-odd rule, a ray towards +x
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
    if (DistanceToSegment(p, a, b) <= margin_m) return false;
  }
  return inside;
}

bool IsSimplePolygon(const std::vector<Eigen::Vector2d>& outline) {
  const size_t n = outline.size();
  if (n < 3) return false;
  for (size_t i = 0; i < n; ++i) {
    if ((outline[i] - outline[(i + 1) % n]).norm() < 1e-9) return false;  // repeated vertex
    for (size_t j = i + 1; j < n; ++j) {
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      const Eigen::Vector2d &a = outline[i], &b = outline[(i + 1) % n];
      const Eigen::Vector2d &c = outline[j], &d = outline[(j + 1) % n];
      if (!neighbours) {
        if (SegmentsMeet(a, b, c, d)) return false;
      } else if (std::abs(Cross(b - a, d - c)) < 1e-12 && (b - a).dot(d - c) < 0) {
        return false;  // a wall that doubles back on its neighbour
      }
    }
  }
  return true;
}

std::vector<MapCorner> RightAngleCorners(const std::string& room_id,
                                         const std::vector<Eigen::Vector2d>& outline,
                                         double ceiling_height_m, double tolerance_rad) {
  std::vector<MapCorner> out;
  const size_t n = outline.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& v = outline[i];
    const Eigen::Vector2d to_previous = (outline[(i + n - 1) % n] - v).normalized();
    const Eigen::Vector2d to_next = (outline[(i + 1) % n] - v).normalized();
    // Counter-clockwise: the room lies left of each wall, so at a vertex it sees the room
    // inside the angle from to_next round to to_previous; a right angle with the room inside
    // turns counter-clockwise by +90 degrees (a reflex vertex by -90).
    const double turn = std::atan2(Cross(to_next, to_previous), to_next.dot(to_previous));
    if (std::abs(turn - M_PI / 2) > tolerance_rad) continue;
    MapCorner c;
    c.id = room_id + "-" + std::to_string(i);
    c.room_id = room_id;
    c.position_m = v;
    // X x Y must point down: Cross(X, Y) < 0 seen from above.
    c.x_edge = to_previous;
    c.y_edge = to_next;
    c.ceiling_height_m = ceiling_height_m;
    out.push_back(c);
  }
  return out;
}

bool CornerInSight(const MapRoom& room, const MapCorner& corner, const Eigen::Vector2d& camera_m) {
  const auto& o = room.outline_m;
  const size_t n = o.size();
  // Stop the sight line just short of the corner, where it meets the corner's own walls.
  const Eigen::Vector2d to_corner = corner.position_m - camera_m;
  const double length = to_corner.norm();
  if (length < 1e-9) return false;
  const Eigen::Vector2d end = camera_m + to_corner * (1 - 1e-6 / length);
  for (size_t i = 0; i < n; ++i) {
    if (SegmentsMeet(camera_m, end, o[i], o[(i + 1) % n])) return false;
  }
  return true;
}

const MapRoom* RoomContaining(const RoomMap& map, const Eigen::Vector2d& p, double margin_m) {
  for (const MapRoom& room : map.rooms)
    if (InsideOutline(room.outline_m, p, margin_m)) return &room;
  return nullptr;
}

Eigen::Isometry3d MapFromCorner(const MapCorner& corner) {
  Eigen::Matrix3d axes;
  axes.col(0) << corner.x_edge, 0;
  axes.col(1) << corner.y_edge, 0;
  axes.col(2) << 0, 0, -1;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = axes;
  t.translation() << corner.position_m, corner.ceiling_height_m;
  return t;
}

}  // namespace monocle
