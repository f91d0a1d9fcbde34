// monocled's configuration: the text-protobuf file (idl/service_config.proto) turned into
// validated values once, at the boundary. Errors name the file, the line and the field.
#pragma once

#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/aravis/aravis_options.h"
#include "camera/recording_source.h"
#include "service/common/result.h"
#include "service/geometry/map_pose.h"
#include "service/geometry/robot_frames.h"
#include "service/geometry/room_map.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle {

enum class CameraRole { kCorner, kFloor, kCornerAndFloor };

const char* ToString(CameraRole role);  // "corner", "floor", "corner+floor"

// `name` with every character a ROS 2 name does not allow (only A-Z a-z 0-9 _) turned into _,
// and a leading digit prefixed with _: "sim-corner" -> "sim_corner".
std::string RosNameToken(const std::string& name);

struct CameraSetup {
  std::string id;         // name on DDS and in requests
  AravisOptions options;  // device and GenICam settings
  CameraRole role = CameraRole::kCorner;
  std::string calibration_path;              // resolved against the config's directory
  std::optional<double> ceiling_distance_m;  // overrides the calibration file's
  std::chrono::milliseconds stall_timeout{1000};
  // ROS 2 names (see idl/service_config.proto): the namespace starts with '/', no trailing '/'.
  std::string ros_namespace;     // e.g. /monocle/sim_corner
  std::string ros_parent_frame;  // frame the pose and tf are given in, e.g. corner
  std::string ros_frame;         // the camera's optical frame, e.g. sim_corner_optical
  double image_max_rate_hz = 5;
  // The camera on the robot (idl/service_config.proto CameraMount), if configured.
  struct Mount {
    std::string base_frame;
    std::array<double, 3> translation_m{};
    std::array<double, 4> rotation_xyzw{0, 0, 0, 1};  // as configured (norm 1 within 1e-3)
  };
  std::optional<Mount> mount;
  // How level the robot stands (level_sigma_deg), radians; set only if configured.
  std::optional<double> level_sigma_rad;
  // A room map (service/README.md, "Room map"), loaded and checked against the mount, and where the
  // robot starts in it.
  std::shared_ptr<const RoomMap> room_map;
  std::string room_map_path;
  std::optional<BasePose2d> initial_pose;
  // Frames from a recording instead of a device (`monocled --replay`, replay_setup.h): the
  // MCAP file, the namespace the camera had in it, and the pace.
  struct Replay {
    std::string mcap_path;
    std::string recorded_namespace;
    ReplayPace pace;
  };
  std::optional<Replay> replay;

  bool corner() const { return role != CameraRole::kFloor; }
  bool floor() const { return role != CameraRole::kCorner; }
};

// The mount as a rigid transform (optical frame in the base frame).
RigidTransform MountTransform(const CameraSetup::Mount& mount);

// What a camera's configuration asks of the corner pipeline: its ceiling distance, mount,
// level and room map.
CornerPipelineOptions CornerPipelineOptionsOf(const CameraSetup& camera);

// Limits of a configuration, checked with the field named.
inline constexpr int kMaxCamerasPerService = 64;
inline constexpr size_t kMaxNameLength = 128;  // a camera's id or device

// Which Gid layout ros_discovery_info is written in (ros_discovery_info.h), or none.
enum class RosDiscoveryLayout { kIronAndLater, kHumble, kOff };

struct ServiceSetup {
  int domain = 0;
  std::string security_dir;  // DDS Security identity directory; empty: plain DDS
  std::vector<CameraSetup> cameras;
  std::chrono::milliseconds status_period{1000};
  // Listening for the services already on the domain at start (duplicate_watch.h).
  std::chrono::milliseconds discovery_wait{1000};
  RosDiscoveryLayout ros_discovery = RosDiscoveryLayout::kIronAndLater;
};

// `source` names the file in messages; relative calibration paths resolve against `base_dir`.
Result<ServiceSetup> ParseServiceConfig(const std::string& text, const std::string& source,
                                        const std::string& base_dir);
Result<ServiceSetup> LoadServiceConfig(const std::string& path);

// The configuration used when monocled is given none: the in-process simulated cameras
// sim-corner and sim-floor, with calibration files in the state directory (see
// EnsureSimulatorCalibrations). `calibration_dir` empty: the paths are relative to it;
// else they are spelled in that folder, so the text works as a --config of its own.
std::string EmbeddedDefaultConfig(const std::string& calibration_dir = "");

}  // namespace monocle
