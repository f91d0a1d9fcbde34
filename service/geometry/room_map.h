// Rooms and their ceiling corners in one map frame, and what a camera inside a room can see.
// Pure geometry: Eigen only, no I/O (service/io/room_map_file reads and validates the file).
//
// Map frame M: x, y on the floor (metres), z up from the floor. A corner's frame G is the one
// of service/geometry/corner_pose.h: origin at the corner on the ceiling, X and Y along the
// two ceiling edges, Z down the wall edge, right-handed; the room is x, y, z > 0 in it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace monocle {

struct MapCorner {
  std::string id;
  std::string room_id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // on the floor plan
  Eigen::Vector2d x_edge = Eigen::Vector2d::UnitX();     // unit, along the corner frame's X
  Eigen::Vector2d y_edge = Eigen::Vector2d::UnitY();     // unit, along Y; X x Y points down
  double ceiling_height_m = 0;
};

struct MapRoom {
  std::string id;
  std::vector<Eigen::Vector2d> outline_m;  // counter-clockwise seen from above
  double ceiling_height_m = 0;
  std::vector<MapCorner> corners;
};

struct RoomMap {
  std::vector<MapRoom> rooms;
};

std::ostream& operator<<(std::ostream& os, const MapCorner& c);

// Twice the signed area: > 0 for a counter-clockwise outline.
double SignedDoubleArea(const std::vector<Eigen::Vector2d>& outline);

// Strictly inside, at least `margin_m` from every wall.
bool InsideOutline(const std::vector<Eigen::Vector2d>& outline, const Eigen::Vector2d& p,
                   double margin_m = 0);

// True if the outline's edges meet only at shared vertices (a simple polygon).
bool IsSimplePolygon(const std::vector<Eigen::Vector2d>& outline);

// The corners of a counter-clockwise outline: every vertex where the walls meet at a right
// angle (within `tolerance_rad`) with the room inside that angle. Ids "<room>-<vertex index>".
std::vector<MapCorner> RightAngleCorners(const std::string& room_id,
                                         const std::vector<Eigen::Vector2d>& outline_ccw,
                                         double ceiling_height_m, double tolerance_rad);

// Whether a camera at `camera_m` (floor-plan position) inside `room` sees the corner without a
// wall in between: the sight line to the corner crosses no wall but the corner's own two.
bool CornerInSight(const MapRoom& room, const MapCorner& corner, const Eigen::Vector2d& camera_m);

// The room whose outline holds `p` (at least `margin_m` inside), or nullptr.
const MapRoom* RoomContaining(const RoomMap& map, const Eigen::Vector2d& p, double margin_m = 0);

// T_map_corner: corner-frame points into the map frame.
Eigen::Isometry3d MapFromCorner(const MapCorner& corner);

}  // namespace monocle
