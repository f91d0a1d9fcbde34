// monocle's wire: topic and service names and QoS, written once for the service and the
// client library. Everything follows ROS 2's conventions on Cyclone DDS (rmw_cyclonedds_cpp),
// so ROS 2 nodes read and call the same endpoints monocle's own clients use:
//   rt/<ros name> for topics; rq/<service>Request and rr/<service>Reply for services; types
//   from idl/ros/ (ROS 2's standard messages, and monocle_msgs for monocle's own).
#pragma once

#include <string>

#include "idl/protocol/dds.h"

namespace monocle::wire {

// Every camera of every monocled on the domain (monocle_msgs/CameraStatus) and their
// calibrations (monocle_msgs/Calibration): one writer per camera, transient-local, so a late
// reader gets each camera's latest at once. ROS: /monocle/cameras, /monocle/calibrations.
inline constexpr const char* kCamerasTopic = "rt/monocle/cameras";
inline constexpr const char* kCalibrationsTopic = "rt/monocle/calibrations";

// Per camera, under its namespace `ns` (e.g. /monocle/sim_corner):
inline std::string CornerPoseTopic(const std::string& ns) { return "rt" + ns + "/corner_pose"; }
inline std::string RosTopic(const std::string& ns, const std::string& leaf) {
  return "rt" + ns + "/" + leaf;
}
// Services of a camera: measure_points, get_pose, calibrate_floor.
inline constexpr const char* kMeasurePoints = "measure_points";
inline constexpr const char* kGetPose = "get_pose";
inline constexpr const char* kCalibrateFloor = "calibrate_floor";
inline std::string RequestTopic(const std::string& ns, const std::string& service) {
  return "rq" + ns + "/" + service + "Request";
}
inline std::string ReplyTopic(const std::string& ns, const std::string& service) {
  return "rr" + ns + "/" + service + "Reply";
}

// ROS 2's default QoS (rmw_qos_profile_default, also its services' default): reliable,
// volatile, keep-last 10. A reliable writer reaches reliable and best-effort readers; a
// volatile writer does not match a transient-local reader.
inline constexpr dds::EndpointQos kRosDefaultQos{10, false};
// Requests are taken by the service's handler at once; a deeper reader history keeps a burst
// from many clients (history is not matched between writer and reader, so ROS still matches).
inline constexpr dds::EndpointQos kRequestReaderQos{64, false};
// Every reply goes to every client's reply reader: with ROS's depth of 10, 32 clients asking
// at once made the writer drop replies a slow reader had not yet acknowledged
// (bench/hostile_load). Kept in the writer only until acknowledged.
inline constexpr dds::EndpointQos kReplyWriterQos{10, false};
// The largest sample the service sends or takes: a 100 000-point reply is 7.6 MB, and up to
// 14 MB when every point failed with its reason; a request is 3.2 MB. Larger ones are dropped
// by Cyclone as their first fragment arrives, unanswered and before any memory is spent on
// them (a 50 M-point request is 1.6 GB).
inline constexpr size_t kMaxSampleBytes = 16u << 20;
// Points in one measure_points request; the client library refuses more before sending (a
// larger sample would be dropped unanswered), the service refuses more with a typed error.
inline constexpr size_t kMaxPointsPerRequest = 100000;
// Directory topics (cameras, calibrations): each writer keeps its camera's latest.
inline constexpr dds::EndpointQos kDirectoryWriterQos{1, true};
// A reader of them keeps every camera's (the topic has no key: history is per reader).
inline constexpr dds::EndpointQos kDirectoryReaderQos{256, true};

}  // namespace monocle::wire
