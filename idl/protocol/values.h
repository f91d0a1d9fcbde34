// monocle's values: what the service measures and says, in C++ terms. The client library
// returns them and the protocol layer (idl/protocol/) converts them to and from the wire;
// the service builds them too, so each conversion is written once.
// Units: metres, radians, pixels, nanoseconds; frames: idl/README.md, "Frames and units".
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// PixelQuery, PointStatus, MeasuredPoint: the core's types (service/common/point_query.h).
#include "monocle/point_query.h"
// FloorAccuracyTarget, FloorGuidance: the core's (service/common/floor_report.h).
#include "monocle/floor_report.h"

// The library is built with hidden symbols; this marks its public interface.
#if defined(__GNUC__)
#define MONOCLE_CLIENT_API __attribute__((visibility("default")))
#else
#define MONOCLE_CLIENT_API
#endif

namespace monocle {

// Where a pose stands in a room map (monocle_msgs/CornerPose MAP_*).
enum class MapStatus : uint8_t {
  kNone = 0,              // no map configured, or no corner pose in this frame
  kLocated = 1,           // one map corner fits: map_* hold the robot's pose
  kAmbiguous = 2,         // several fit (map_candidates); none is guessed
  kContradictsPrior = 3,  // corners fit, none near the last pose
  kNoCornerFits = 4,      // no map corner is consistent with the view
};
MONOCLE_CLIENT_API const char* ToString(MapStatus status);  // "", "located", "ambiguous", ...

struct Pose {
  std::string camera_id;
  std::string frame_id;         // the corner frame's name (configuration's ros_parent_frame)
  uint64_t frame_sequence = 0;  // the camera's frame id
  int64_t capture_time_ns = 0;  // Unix time of reception (or camera time if camera_clock)
  bool camera_clock = false;    // capture_time_ns is the camera's PTP clock
  bool valid = false;           // false: no corner in this frame, see `error`
  std::string error;
  double x_m = 0, y_m = 0, z_m = 0;                 // camera in the corner frame
  double pan_rad = 0, tilt_rad = 0, swing_rad = 0;  // Chou & Tsai eq. (1)
  std::array<double, 4> quaternion_wxyz{};          // camera (OpenCV axes) -> corner frame
  std::array<double, 25> covariance{};              // row-major 5x5 of (x, y, pan, tilt, swing)
  std::array<double, 2> corner_px{};
  double rms_px = 0;          // edge points to fitted lines
  int64_t processing_ns = 0;  // frame received -> pose computed
  bool tracked = false;       // followed from the previous frame's edges (false: detected)
  bool suspect = false;       // the edges support the pose poorly; `suspect_reason` says how
  std::string suspect_reason;
  // In the room map the camera's configuration names (service/README.md, "Room map"): which map
  // corner, and the robot base in the map frame. kNone without a map or without a corner pose.
  MapStatus map_status = MapStatus::kNone;
  std::string map_corner, map_room;                      // kLocated
  double map_x_m = 0, map_y_m = 0, map_heading_rad = 0;  // base; heading from +x to +y
  std::array<double, 9> map_covariance{};                // row-major 3x3 of (x, y, heading)
  std::array<double, 3> map_camera_position_m{};         // optical centre in the map
  std::array<double, 4> map_camera_quaternion_wxyz{};    // optical frame -> map
  uint32_t map_candidates = 0;                           // corners that fit (> 1: ambiguous)
  std::string map_reason;                                // why not located, in words
  // With the camera's mount and level_sigma_deg and no room map, the pose is combined with the
  // robot's level (client/cli/GUIDE.md, "On a robot: the mount's level"): how far the pose as
  // solved tipped the robot base from level, and the level's 1 sigma. Both 0 when no level was
  // applied.
  double level_error_rad = 0, level_sigma_rad = 0;
  // With the camera's mount: the robot base in the corner frame (as /tf shows it without a
  // room map). base_known is false without a mount or without a corner pose.
  bool base_known = false;
  std::array<double, 3> base_position_m{};       // base origin in the corner frame (Z down)
  std::array<double, 4> base_quaternion_wxyz{};  // base frame -> corner frame
  double base_heading_rad = 0;                   // base +x from the corner's X towards Y
  std::array<double, 9> base_covariance{};       // row-major 3x3 of (x, y, heading)
};

enum class PoseWhich { kLatest, kNextFrame };

// One state type from the camera up to the client. kReconnecting: not streaming but retried
// (camera not found yet, lost, stalled). kFailed: a permanent error, reported once and not
// retried (a configuration the camera cannot take, or a camera namespace another monocled
// already serves): see last_error, fix the configuration and restart.
enum class CameraState : uint8_t { kStreaming = 0, kReconnecting = 1, kStopped = 2, kFailed = 3 };
MONOCLE_CLIENT_API const char* ToString(
    CameraState state);  // "streaming", "reconnecting", "stopped", "failed"

struct CameraStatus {
  std::string camera_id, device, role;  // role: "corner", "floor" or "corner+floor"
  std::string ros_namespace;            // its topics and services, e.g. /monocle/sim_floor
  std::string service;                  // the monocled that owns it: host/pid
  // The DDS participant its status came from (GUID, hex; empty if unknown): two services
  // claiming one namespace differ here even when one copies the other's service id.
  std::string participant;
  CameraState state = CameraState::kReconnecting;
  double fps = 0;         // frames per second over the last status period
  uint64_t frames = 0;    // received since the service started
  uint64_t dropped = 0;   // sent by the camera, never received
  uint64_t skipped = 0;   // not processed because processing was busy
  double latency_ms = 0;  // frame received -> result published, median of the period
  std::string last_error;
  int64_t last_error_ns = 0;  // Unix time, 0 if none
  int64_t stamp_ns = 0;       // Unix time of this status
};

struct FloorPoseEstimate {
  double height_m = 0, pitch_rad = 0, yaw_rad = 0, roll_rad = 0;
  std::array<double, 4> sigma{};  // 1-sigma of height (m), pitch, yaw, roll (rad)
  double rms_px = 0;
};

// What a floor calibration is asked for beyond the board (monocle_msgs/CalibrateFloor).
struct FloorCalibrationOptions {
  double pixel_sigma_px = 0.5;  // noise of a query pixel, for the report's 1 sigma figures
  std::optional<FloorAccuracyTarget> target;  // the accuracy wanted: the report judges it
  bool force = false;    // store a height outside 0.05-10 m, refused as a likely unit slip
  bool overlay = false;  // send back the result drawn over the frame (overlay_png)
};

struct FloorCalibrationResult {
  FloorPoseEstimate floor;
  uint32_t corners = 0;         // board corners used
  uint64_t frame_sequence = 0;  // the frame calibrated from
  std::string file;             // written (atomically) on the service's machine
  uint64_t revision = 0;        // of the calibration now published
  // Where the board lay, the 1 sigma of a floor point ahead, the target, advice (no
  // `suggestions`: their advice says them in words).
  FloorGuidance report;
  std::vector<uint8_t> overlay_png;  // asked for: the result drawn over the frame, PNG
};

struct Calibration {
  std::string camera_id;
  std::string ros_namespace;
  uint64_t revision = 0;
  int64_t updated_ns = 0;
  int width_px = 0, height_px = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  std::array<double, 8> distortion{};     // OpenCV k1 k2 p1 p2 k3 k4 k5 k6
  std::optional<FloorPoseEstimate> floor;
  std::optional<double> ceiling_distance_m;
  std::string file;  // on the service's machine
  std::string text;  // the calibration file's contents (text protobuf)
};

}  // namespace monocle
