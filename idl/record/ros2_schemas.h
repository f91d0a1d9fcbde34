// The ROS 2 message definitions (MCAP schema encoding `ros2msg`) of everything monocle
// records, so Foxglove and `ros2 bag` decode a recording's CDR messages: ROS 2's standard
// messages (written from ROS 2 Humble's .msg files) and monocle_msgs (idl/ros/monocle_msgs,
// embedded at build time). A definition is the type's .msg text followed by each type it
// uses, each after a line of 80 '=' and a line "MSG: pkg/Type" (the MCAP registry's format).
#pragma once

#include <optional>
#include <string>

namespace monocle::record {

// `type` as "pkg/msg/Type" (e.g. "geometry_msgs/msg/PoseWithCovarianceStamped"); nullopt if
// monocle does not know it.
std::optional<std::string> Ros2MsgDefinition(const std::string& type);

// A service sample as rmw_cyclonedds puts it on the wire: its request header (uint64 guid,
// int64 seq) and the request's or the response's fields. `service` as
// "monocle_msgs/srv/MeasurePoints"; nullopt if unknown.
std::optional<std::string> Ros2ServiceSampleDefinition(const std::string& service, bool request);

}  // namespace monocle::record
