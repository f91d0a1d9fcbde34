#include "service/io/room_map_file.h"

#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "idl/room_map.pb.h"
#include "idl/service_config.pb.h"
#include "service/io/bounded_file.h"
#include "service/io/field_errors.h"
#include "service/io/text_proto.h"

namespace monocle {
namespace {

using google::protobuf::TextFormat;

std::string Metres(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v << " m";
  return s.str();
}

std::string Degrees(const Eigen::Vector2d& direction) {
  return std::to_string(std::lround(std::atan2(direction.y(), direction.x()) * 180 / M_PI));
}

bool Finite(double v) { return std::isfinite(v); }

// Rooms are at most a few hundred metres across; a coordinate beyond is a unit mistake.
constexpr double kMaxCoordinateM = 1e4;
constexpr int kMaxRooms = 1000, kMaxVertices = 1000;
constexpr double kRightAngleToleranceRad = 1.0 * M_PI / 180;
constexpr double kOnVertexM = 0.01;

}  // namespace

Result<RoomMap> ParseRoomMap(const std::string& text, const std::string& source) {
  proto::RoomMap msg;
  TextFormat::ParseInfoTree tree;
  if (auto parsed = ParseTextProto(text, source, &msg, &tree); !parsed) return parsed.error();
  const FieldErrors errors(source, tree, proto::RoomMap::descriptor());
  if (msg.room_size() == 0)
    return MakeError(
        ErrorCode::kInvalidArgument,
        source + ": no room { ... } in the map (service/README.md, \"Room map\", has an example)");
  if (msg.room_size() > kMaxRooms)
    return errors.At({{"room", kMaxRooms}}, "is one room too many (at most 1000)");
  RoomMap out;
  std::set<std::string> room_ids, corner_ids;
  for (int r = 0; r < msg.room_size(); ++r) {
    const proto::Room& in = msg.room(r);
    MapRoom room;
    room.id = in.id().empty() ? "room" + std::to_string(r) : in.id();
    if (!room_ids.insert(room.id).second)
      return errors.At({{"room", r}, {"id"}}, "'" + room.id + "' names two rooms");
    if (!(in.ceiling_height_m() > 0.5 && in.ceiling_height_m() < 100))
      return errors.At({{"room", r}, {"ceiling_height_m"}},
                       "must be the floor-to-ceiling height in metres (0.5..100), not " +
                           std::to_string(in.ceiling_height_m()));
    room.ceiling_height_m = in.ceiling_height_m();
    if (in.outline_size() < 3 || in.outline_size() > kMaxVertices)
      return errors.At({{"room", r}, {"outline"}},
                       "must list 3..1000 vertices of the floor outline, not " +
                           std::to_string(in.outline_size()));
    for (int v = 0; v < in.outline_size(); ++v) {
      const auto& p = in.outline(v);
      if (!Finite(p.x_m()) || !Finite(p.y_m()) || std::abs(p.x_m()) > kMaxCoordinateM ||
          std::abs(p.y_m()) > kMaxCoordinateM)
        return errors.At({{"room", r}, {"outline", v}}, "is not a point within 10 km (metres)");
      room.outline_m.emplace_back(p.x_m(), p.y_m());
    }
    if (!IsSimplePolygon(room.outline_m))
      return errors.At({{"room", r}, {"outline"}},
                       "crosses itself or repeats a vertex: list the walls' ends in order "
                       "round the room");
    if (SignedDoubleArea(room.outline_m) < 0)
      std::reverse(room.outline_m.begin(), room.outline_m.end());
    const std::vector<MapCorner> right_angles =
        RightAngleCorners(room.id, room.outline_m, room.ceiling_height_m, kRightAngleToleranceRad);
    if (in.corner_size() == 0) {
      room.corners = right_angles;
    }
    for (int c = 0; c < in.corner_size(); ++c) {
      const proto::MapCorner& pc = in.corner(c);
      if (!pc.has_position())
        return errors.At({{"room", r}, {"corner", c}, {"position"}}, "is missing");
      const Eigen::Vector2d at(pc.position().x_m(), pc.position().y_m());
      double nearest = INFINITY;
      for (const auto& v : room.outline_m) nearest = std::min(nearest, (v - at).norm());
      if (!(nearest <= kOnVertexM)) {
        const bool outside = !InsideOutline(room.outline_m, at);
        return errors.At({{"room", r}, {"corner", c}, {"position"}},
                         std::string(outside ? "lies outside the room and " : "") +
                             "is not a vertex of room[" + std::to_string(r) +
                             "].outline (the nearest is " + Metres(nearest) + " away)");
      }
      const MapCorner* match = nullptr;
      for (const auto& rc : right_angles)
        if ((rc.position_m - at).norm() <= kOnVertexM) match = &rc;
      if (match == nullptr)
        return errors.At({{"room", r}, {"corner", c}, {"position"}},
                         "is a vertex where the walls do not meet at a right angle with the room "
                         "inside it: a ceiling corner there is not the Y monocle measures");
      if (pc.edge_heading_deg_size() != 0) {
        if (pc.edge_heading_deg_size() != 2)
          return errors.At({{"room", r}, {"corner", c}, {"edge_heading_deg"}},
                           "must give both ceiling edges' headings (2 values), not " +
                               std::to_string(pc.edge_heading_deg_size()));
        for (int e = 0; e < 2; ++e) {
          const double h = pc.edge_heading_deg(e) * M_PI / 180;
          const Eigen::Vector2d dir(std::cos(h), std::sin(h));
          if (!Finite(h) || std::max(dir.dot(match->x_edge), dir.dot(match->y_edge)) <
                                std::cos(kRightAngleToleranceRad))
            return errors.At({{"room", r}, {"corner", c}, {"edge_heading_deg", e}},
                             "does not run along a wall of the outline from this corner "
                             "(the walls run at " +
                                 Degrees(match->x_edge) + " and " + Degrees(match->y_edge) +
                                 " degrees)");
        }
      }
      MapCorner corner = *match;
      if (!pc.id().empty()) corner.id = pc.id();
      room.corners.push_back(corner);
    }
    for (size_t c = 0; c < room.corners.size(); ++c) {
      if (!corner_ids.insert(room.corners[c].id).second)
        return errors.At({{"room", r}, {"corner", static_cast<int>(c)}, {"id"}},
                         "'" + room.corners[c].id + "' names two corners");
    }
    if (room.corners.empty())
      return errors.At({{"room", r}, {"outline"}},
                       "has no right-angle corner: monocle needs one to locate itself");
    out.rooms.push_back(std::move(room));
  }
  return out;
}

Result<RoomMap> LoadRoomMapFile(const std::string& path) {
  auto text = ReadBoundedFile(path, "room map", kMaxTextFileBytes);
  if (!text) return text.error();
  return ParseRoomMap(*text, path);
}

Result<RigidTransform> ParseCameraMount(const std::string& text, const std::string& source,
                                        const RoomMap& map) {
  proto::CameraMount msg;
  TextFormat::ParseInfoTree tree;
  if (auto parsed = ParseTextProto(text, source, &msg, &tree); !parsed) return parsed.error();
  const FieldErrors errors(source, tree, proto::CameraMount::descriptor());
  if (msg.translation_m_size() != 3)
    return errors.At({{"translation_m"}},
                     "must be x, y, z of the optical centre in the base frame (metres; z its "
                     "height above the floor), 3 values");
  if (msg.rotation_xyzw_size() != 4)
    return errors.At({{"rotation_xyzw"}},
                     "must be the optical frame's orientation in the base frame, a unit "
                     "quaternion x, y, z, w (4 values)");
  RigidTransform out;
  for (int i = 0; i < 3; ++i) {
    if (!Finite(msg.translation_m(i)) || std::abs(msg.translation_m(i)) > 100)
      return errors.At({{"translation_m", i}}, "must be a distance in metres (within 100 m)");
    out.translation[i] = msg.translation_m(i);
  }
  const Eigen::Quaterniond q(msg.rotation_xyzw(3), msg.rotation_xyzw(0), msg.rotation_xyzw(1),
                             msg.rotation_xyzw(2));
  if (!std::isfinite(q.norm()) || std::abs(q.norm() - 1) > 1e-3)
    return errors.At({{"rotation_xyzw"}},
                     "must be a unit quaternion (its norm is " + std::to_string(q.norm()) + ")");
  out.rotation = q.normalized();
  if (!(out.translation.z() > 0))
    return errors.At({{"translation_m", 2}},
                     "is the optical centre's height above the floor: it must be above 0 m");
  for (const MapRoom& room : map.rooms) {
    if (out.translation.z() >= room.ceiling_height_m)
      return errors.At({{"translation_m", 2}},
                       "puts the camera " + Metres(out.translation.z()) +
                           " above the floor, at or above the ceiling of room '" + room.id + "' (" +
                           Metres(room.ceiling_height_m) + ")");
  }
  return out;
}

Result<RigidTransform> LoadCameraMountFile(const std::string& path, const RoomMap& map) {
  auto text = ReadBoundedFile(path, "camera mount", kMaxTextFileBytes);
  if (!text) return text.error();
  return ParseCameraMount(*text, path, map);
}

}  // namespace monocle
