#include "service/geometry/map_pose.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

namespace monocle {
namespace {

double WrapAngle(double a) { return std::remainder(a, 2 * M_PI); }

// The camera and base in the map for corner-pose parameters (x, y, pan, tilt, swing) solved
// at ceiling distance z0, placed at `corner` (whose ceiling distance may differ).
struct Placed {
  RigidTransform map_camera;
  BasePose2d base;
};

Placed Place(const MapCorner& corner, const RigidTransform& base_camera, CornerPose p,
             double ceiling_distance_m) {
  const double scale = ceiling_distance_m / p.z_m;
  p.x_m *= scale;
  p.y_m *= scale;
  p.z_m = ceiling_distance_m;
  const Eigen::Isometry3d map_corner = MapFromCorner(corner);
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(p).transpose();
  RigidTransform map_camera;
  map_camera.rotation = Eigen::Quaterniond(map_corner.linear() * corner_from_camera);
  map_camera.translation = map_corner * CameraPosition(p);
  const RigidTransform map_base = BaseInParent(map_camera, base_camera);
  const Eigen::Vector3d forward = map_base.rotation * Eigen::Vector3d::UnitX();
  return {map_camera, BasePose2d{map_base.translation.x(), map_base.translation.y(),
                                 std::atan2(forward.y(), forward.x())}};
}

// Length of the wall a corner's edge runs along: to the neighbouring vertex in that direction
// (X, Y), or the ceiling height (Z).
double WallLength(const MapRoom& room, const MapCorner& corner, int axis) {
  if (axis == 2) return corner.ceiling_height_m;
  const Eigen::Vector2d& dir = axis == 0 ? corner.x_edge : corner.y_edge;
  double best = 0;
  const auto& o = room.outline_m;
  for (size_t i = 0; i < o.size(); ++i) {
    const size_t j = (i + 1) % o.size();
    // The wall from the corner's vertex along `dir`.
    for (auto [a, b] : {std::pair{i, j}, std::pair{j, i}}) {
      if ((o[a] - corner.position_m).norm() > 1e-6) continue;
      const Eigen::Vector2d wall = o[b] - o[a];
      if (wall.normalized().dot(dir) > 1 - 1e-6) best = std::max(best, wall.norm());
    }
  }
  return best;
}

// The ceiling edge of the wall after the one a corner's edge (X or Y) runs along: from that
// wall's far vertex on to the next, at the ceiling (map frame). Nothing for Z.
std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> NextCeilingEdge(const MapRoom& room,
                                                                           const MapCorner& corner,
                                                                           int axis) {
  if (axis == 2) return std::nullopt;
  const Eigen::Vector2d& dir = axis == 0 ? corner.x_edge : corner.y_edge;
  const auto& o = room.outline_m;
  const size_t n = o.size();
  for (size_t a = 0; a < n; ++a) {
    if ((o[a] - corner.position_m).norm() > 1e-6) continue;
    for (const size_t b : {(a + 1) % n, (a + n - 1) % n}) {
      if ((o[b] - o[a]).normalized().dot(dir) < 1 - 1e-6) continue;
      const size_t c = b == (a + 1) % n ? (b + 1) % n : (b + n - 1) % n;
      const double h = corner.ceiling_height_m;
      return std::pair{Eigen::Vector3d(o[b].x(), o[b].y(), h),
                       Eigen::Vector3d(o[c].x(), o[c].y(), h)};
    }
  }
  return std::nullopt;
}

// Whether the ray from `camera` along `ray` (map frame) meets the segment within 1 % of its
// range (about a pixel at 1000 px focal length, five at 200 px... generous for a seen end).
bool RayMeetsSegment(const Eigen::Vector3d& camera, const Eigen::Vector3d& ray,
                     const std::pair<Eigen::Vector3d, Eigen::Vector3d>& segment) {
  const Eigen::Vector3d r = ray.normalized();
  const Eigen::Vector3d d = segment.second - segment.first;
  const Eigen::Vector3d w = camera - segment.first;
  const double dd = d.dot(d), rd = r.dot(d), wr = w.dot(r), wd = w.dot(d);
  const double det = dd - rd * rd;     // |r| = 1
  if (det < 1e-12 * dd) return false;  // parallel
  // Closest points camera + t r and first + s d, s held to the segment.
  const double s = std::clamp((wd - rd * wr) / det, 0.0, 1.0);
  const Eigen::Vector3d q = segment.first + s * d;
  const double t = (q - camera).dot(r);
  if (t <= 0) return false;
  return (camera + t * r - q).norm() <= 0.01 * t;
}

}  // namespace

double SeenEdgeExtent(const CameraIntrinsics& intrinsics, const CornerPose& pose, int axis,
                      const Eigen::Vector2d& end_px) {
  const auto normalized = PixelToNormalized(intrinsics, end_px);
  if (!normalized) return 0;
  // The ray c + t r and the axis s e (corner frame) pass closest where their difference is
  // perpendicular to both.
  const Eigen::Vector3d c = CameraPosition(pose);
  const Eigen::Vector3d r = RotationCameraFromCorner(pose).transpose() *
                            Eigen::Vector3d(normalized->x(), normalized->y(), 1);
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
  const double re = r.dot(e), rr = r.dot(r);
  const double det = rr - re * re;  // |e| = 1
  if (det < 1e-12 * rr) return 0;
  // Minimise |c + t r - s e|^2: t rr - s re = -c.r, t re - s = -c.e.
  const double cr = c.dot(r), ce = c.dot(e);
  const double s = (rr * ce - re * cr) / det;
  return std::max(0.0, s);
}

SeenEdgeExtents SeenEdgeExtentsAtLeast(const CameraIntrinsics& intrinsics, const CornerPose& pose,
                                       const Eigen::Vector2d& corner_px,
                                       const std::array<Eigen::Vector2d, 3>& end_px,
                                       double margin_px) {
  SeenEdgeExtents out{};
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector2d along = end_px[axis] - corner_px;
    if (along.norm() <= margin_px) continue;
    const Eigen::Vector2d end = end_px[axis] - margin_px * along.normalized();
    out.along[axis] = SeenEdgeExtent(intrinsics, pose, axis, end);
    if (const auto normalized = PixelToNormalized(intrinsics, end)) {
      out.end_ray_corner[axis] = (RotationCameraFromCorner(pose).transpose() *
                                  Eigen::Vector3d(normalized->x(), normalized->y(), 1))
                                     .normalized();
    }
  }
  return out;
}

std::ostream& operator<<(std::ostream& os, const BasePose2d& p) {
  return os << "BasePose2d{x " << p.x_m << " m, y " << p.y_m << " m, heading "
            << p.heading_rad * 180 / M_PI << " deg}";
}

MapPoseCandidate PoseInMapFromCorner(const MapCorner& corner, const RigidTransform& base_camera,
                                     const CornerPose& pose,
                                     const Eigen::Matrix<double, 5, 5>& covariance) {
  const double distance = corner.ceiling_height_m - base_camera.translation.z();
  const Placed placed = Place(corner, base_camera, pose, distance);
  MapPoseCandidate c;
  c.corner_id = corner.id;
  c.room_id = corner.room_id;
  c.corner_pose = pose;
  const double scale = distance / pose.z_m;
  c.corner_pose.x_m *= scale;
  c.corner_pose.y_m *= scale;
  c.corner_pose.z_m = distance;
  c.map_camera = placed.map_camera;
  c.base = placed.base;
  // First-order propagation through Place, by central differences over the five parameters.
  Eigen::Matrix<double, 3, 5> jacobian;
  for (int k = 0; k < 5; ++k) {
    const double step = k < 2 ? 1e-6 * pose.z_m : 1e-7;
    CornerPose plus = pose, minus = pose;
    double* fields_plus[5] = {&plus.x_m, &plus.y_m, &plus.pan_rad, &plus.tilt_rad, &plus.swing_rad};
    double* fields_minus[5] = {&minus.x_m, &minus.y_m, &minus.pan_rad, &minus.tilt_rad,
                               &minus.swing_rad};
    *fields_plus[k] += step;
    *fields_minus[k] -= step;
    const BasePose2d a = Place(corner, base_camera, plus, distance).base;
    const BasePose2d b = Place(corner, base_camera, minus, distance).base;
    jacobian.col(k) << (a.x_m - b.x_m) / (2 * step), (a.y_m - b.y_m) / (2 * step),
        WrapAngle(a.heading_rad - b.heading_rad) / (2 * step);
  }
  const Eigen::Matrix3d base_covariance = jacobian * covariance * jacobian.transpose();
  // Exactly symmetric, as published on ROS and the wire (J C J^T rounds its triangles apart).
  c.base_covariance = 0.5 * (base_covariance + base_covariance.transpose());
  return c;
}

MapLocation LocateInMap(const RoomMap& map, const RigidTransform& base_camera,
                        const CornerPose& pose_as_solved,
                        const Eigen::Matrix<double, 5, 5>& covariance_as_solved,
                        const std::optional<MapPosePrior>& prior,
                        const SeenEdgeExtents& seen_extents, const MapCheckOptions& checks) {
  MapLocation out;
  const LevelledCornerPose levelled =
      LevelWithMount(pose_as_solved, covariance_as_solved, base_camera, checks.level_sigma_rad);
  const CornerPose& pose = levelled.pose;
  const Eigen::Matrix<double, 5, 5>& covariance = levelled.covariance;
  out.level_error_rad = levelled.level_error_rad;
  if (out.level_error_rad > checks.max_level_error_rad) {
    std::ostringstream why;
    why.precision(2);
    why << std::fixed << "the pose tips the robot " << out.level_error_rad * 180 / M_PI
        << " deg from level (allowed " << checks.max_level_error_rad * 180 / M_PI << " deg)";
    out.suspect = true;
    out.suspect_reason = why.str();
  }
  std::vector<MapPoseCandidate> in_room;
  int outside = 0, hidden = 0, too_short = 0;
  for (const MapRoom& room : map.rooms) {
    for (const MapCorner& corner : room.corners) {
      MapPoseCandidate c = PoseInMapFromCorner(corner, base_camera, pose, covariance);
      const Eigen::Vector2d camera_xy = c.map_camera.translation.head<2>();
      if (!InsideOutline(room.outline_m, camera_xy)) {
        ++outside;
        continue;
      }
      if (!CornerInSight(room, corner, camera_xy)) {
        ++hidden;
        continue;
      }
      // An edge seen further than its wall runs is another wall. Allowance: 25 % (the seen
      // end's ray meets the edge at a grazing angle far away) and 0.3 m (where the next wall's
      // edge runs on nearly in line in the image, its first points join the fit).
      const double scale = c.corner_pose.z_m / pose.z_m;
      bool fits = true;
      const Eigen::Matrix3d map_from_corner = MapFromCorner(corner).linear();
      for (int axis = 0; axis < 3; ++axis) {
        const double seen_m = seen_extents[axis] * scale;
        if (seen_m <= 1.25 * WallLength(room, corner, axis) + 0.3) continue;
        // Further than the wall: fine only if the seen end lies on the next wall's edge.
        const auto next = NextCeilingEdge(room, corner, axis);
        const Eigen::Vector3d& ray = seen_extents.end_ray_corner[axis];
        if (!next || ray.isZero() ||
            !RayMeetsSegment(c.map_camera.translation, map_from_corner * ray, *next))
          fits = false;
      }
      if (!fits) {
        ++too_short;
        continue;
      }
      in_room.push_back(std::move(c));
    }
  }
  if (in_room.empty()) {
    std::ostringstream why;
    why << "no corner of the map is consistent with this view: from " << outside
        << " corner(s) the camera would stand outside the room, from " << hidden
        << " a wall would hide the corner, at " << too_short
        << " an edge was seen further than its wall runs";
    out.why_none = why.str();
    return out;
  }
  if (!prior) {
    out.consistent = std::move(in_room);
    return out;
  }
  auto distance_to_prior = [&](const MapPoseCandidate& c) {
    return std::hypot(c.base.x_m - prior->base.x_m, c.base.y_m - prior->base.y_m);
  };
  for (const MapPoseCandidate& c : in_room) {
    if (distance_to_prior(c) <= prior->max_distance_m &&
        std::abs(WrapAngle(c.base.heading_rad - prior->base.heading_rad)) <= prior->max_heading_rad)
      out.consistent.push_back(c);
  }
  if (out.consistent.empty()) {
    // The prior is wrong or stale (the robot was carried, frames were lost): what the room
    // alone allows stands, unique or ambiguous.
    out.prior_contradicted = true;
    out.consistent = std::move(in_room);
  }
  std::sort(out.consistent.begin(), out.consistent.end(), [&](const auto& a, const auto& b) {
    return distance_to_prior(a) < distance_to_prior(b);
  });
  return out;
}

}  // namespace monocle
