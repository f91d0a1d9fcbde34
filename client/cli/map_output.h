// How `monocle corner locate --map` shows the robot in the map: one text line and the JSON
// object (idl/cli_output.proto MapLocationOutput).
#pragma once

#include <string>

#include "idl/cli_output.pb.h"
#include "service/geometry/map_pose.h"

namespace monocle::cli {

proto::MapLocationOutput ToMapLocationOutput(const MapLocation& where);

// "map: hall-1 (room hall)  base x=5.0004 y=1.3001 m heading=-25.00 deg (1σ ...)" or what
// keeps it from being decided, with the candidates.
std::string MapLocationLine(const MapLocation& where);

// "located", "ambiguous", "contradicts prior" or "no corner fits".
std::string MapStatus(const MapLocation& where);

}  // namespace monocle::cli
