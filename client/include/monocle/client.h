// monocle::Client: a C++ client of the monocle service (monocled) over Cyclone DDS.
//
//   auto client = monocle::Client::open({.domain = 0});
//   if (!client) { std::cerr << client.error() << "\n"; return 1; }
//   auto points = client->measure("sim-floor", {{640, 900}});
//   auto sub = client->subscribe_poses([](const monocle::Pose& p) { ... });
//
// Units: metres, radians, pixels, nanoseconds. Frames: poses are in the corner frame, points
// in the robot frame (README, "Frames and units"). Methods are safe to call from several
// threads; calls of the same kind (e.g. two measure()) run one after the other. Callbacks run
// on a thread of their subscription. Names follow the standard library and cyclonedds-cxx.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

// The library is built with hidden symbols; this marks its public interface.
#if defined(__GNUC__)
#define MONOCLE_CLIENT_API __attribute__((visibility("default")))
#else
#define MONOCLE_CLIENT_API
#endif

namespace monocle {

struct ClientError {
  enum class Code {
    kNoService,       // no monocled answered within the timeout (not running, other domain)
    kInvalidRequest,  // the service rejected the request: unknown camera, bad values, ...
    kFailed,          // the service could not do it: no frame, no board in view, no pose yet
    kDds,             // DDS itself failed (configuration, resources)
  };
  Code code = Code::kFailed;
  std::string message;  // a sentence a user can act on
};

MONOCLE_CLIENT_API std::ostream& operator<<(std::ostream& os, const ClientError& e);

// A value or a ClientError (a small stand-in for C++23 std::expected).
template <typename T>
class ClientResult {
 public:
  ClientResult(T value) : data_(std::move(value)) {}            // NOLINT
  ClientResult(ClientError error) : data_(std::move(error)) {}  // NOLINT
  bool ok() const { return data_.index() == 0; }
  explicit operator bool() const { return ok(); }
  const T& value() const& { return std::get<0>(data_); }
  T& value() & { return std::get<0>(data_); }
  T&& value() && { return std::get<0>(std::move(data_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }
  const ClientError& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, ClientError> data_;
};

// A floor pixel, or a pixel standing vertically above the floor pixel `floor_px`.
struct PixelQuery {
  double u = 0, v = 0;                            // pixels
  std::optional<std::array<double, 2>> floor_px;  // (u, v) of the point's foot on the floor
};

struct MeasuredPoint {
  enum class Status : uint8_t { kMeasured = 0, kInvalidPixel = 1, kNotMeasurable = 2 };
  Status status = Status::kMeasured;
  std::array<double, 3> p_robot_m{};  // x, y, z in the robot frame, metres
  std::array<double, 3> sigma_m{};    // 1-sigma of x, y, z, metres
  std::string error;                  // why not measured
  bool ok() const { return status == Status::kMeasured; }
};

struct Pose {
  std::string camera_id;
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
};

enum class PoseWhich { kLatest, kNextFrame };

enum class CameraState : uint8_t { kStreaming = 0, kReconnecting = 1, kStopped = 2 };
MONOCLE_CLIENT_API const char* ToString(
    CameraState state);  // "streaming", "reconnecting", "stopped"

struct CameraStatus {
  std::string camera_id, device, role;  // role: "corner", "floor" or "corner+floor"
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

struct FloorCalibrationResult {
  FloorPoseEstimate floor;
  uint32_t corners = 0;         // board corners used
  uint64_t frame_sequence = 0;  // the frame calibrated from
  std::string file;             // written (atomically) on the service's machine
  uint64_t revision = 0;        // of the calibration now published
};

struct Calibration {
  std::string camera_id;
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

// Delivers callbacks until destroyed (or stop()); the callback never runs after that.
class MONOCLE_CLIENT_API Subscription {
 public:
  Subscription();
  ~Subscription();
  Subscription(Subscription&&) noexcept;
  Subscription& operator=(Subscription&&) noexcept;
  void stop();

  struct State;  // implementation

 private:
  friend class Client;
  std::unique_ptr<State> state_;
};

class MONOCLE_CLIENT_API Client {
 public:
  struct Options {
    int domain = 0;                           // DDS domain of the service
    std::chrono::milliseconds timeout{5000};  // per request, including finding the service
  };

  static ClientResult<Client> open(Options options);
  static ClientResult<Client> open() { return open(Options{}); }
  ~Client();
  Client(Client&&) noexcept;
  Client& operator=(Client&&) noexcept;

  // Floor pixels -> robot-frame points with 1-sigma, one result per pixel, in order (a bad
  // pixel is a result with its own error). `pixel_sigma_px` 0: the service's default 0.5 px.
  ClientResult<std::vector<MeasuredPoint>> measure(const std::string& camera,
                                                   const std::vector<PixelQuery>& pixels,
                                                   double pixel_sigma_px = 0);
  // The latest pose of a corner camera, or the pose of its next frame.
  ClientResult<Pose> pose(const std::string& camera, PoseWhich which = PoseWhich::kLatest);
  // Calibrates a floor camera from its next frame showing a chessboard lying on the floor
  // (cols x rows inner corners, squares of `square_m`); the service stores and publishes it.
  ClientResult<FloorCalibrationResult> calibrate_floor(const std::string& camera, int board_cols,
                                                       int board_rows, double square_m);
  // The current status and calibration of every camera.
  ClientResult<std::vector<CameraStatus>> status();
  ClientResult<std::vector<Calibration>> calibrations();

  // Every pose (of `camera`, or of all cameras when empty) as it is published.
  ClientResult<Subscription> subscribe_poses(std::function<void(const Pose&)> on_pose,
                                             const std::string& camera = "");
  // Every camera's status as it is published (each status period, and on changes).
  ClientResult<Subscription> subscribe_status(std::function<void(const CameraStatus&)> on_status);

  struct Impl;  // implementation

 private:
  explicit Client(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace monocle
