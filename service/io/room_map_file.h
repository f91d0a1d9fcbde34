// Room map files (idl/room_map.proto, text format) and camera mount files (CameraMount of
// idl/service_config.proto), validated on load: every error names the line and the field,
// e.g. "room.pbtxt: line 12: room[0].corner[1].position is not a vertex of room[0].outline
// (the nearest is 0.80 m away)".
#pragma once

#include <string>

#include "service/common/result.h"
#include "service/geometry/robot_frames.h"
#include "service/geometry/room_map.h"

namespace monocle {

// Outlines come back counter-clockwise whatever their winding in the file; corners listed in
// a room must be right-angle vertices of its outline with their edges along its walls; a room
// without listed corners gets its right-angle vertices (ids "<room>-<vertex index>").
Result<RoomMap> ParseRoomMap(const std::string& text, const std::string& source);
Result<RoomMap> LoadRoomMapFile(const std::string& path);

// The camera's mount: its translation's z is the optical centre's height above the floor,
// which must lie below every room's ceiling in `map`.
Result<RigidTransform> ParseCameraMount(const std::string& text, const std::string& source,
                                        const RoomMap& map);
Result<RigidTransform> LoadCameraMountFile(const std::string& path, const RoomMap& map);

}  // namespace monocle
