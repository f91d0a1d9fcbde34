// monocle::Client: a C++ client of the monocle service (monocled) over Cyclone DDS.
//
//   auto client = monocle::Client::open({.domain = 0});
//   if (!client) { std::cerr << client.error() << "\n"; return 1; }
//   auto points = client->measure("sim-floor", {{640, 900}});
//   auto sub = client->subscribe_poses([](const monocle::Pose& p) { ... });
//
// Units: metres, radians, pixels, nanoseconds. Frames: poses are in the corner frame, points
// in the robot frame (idl/README.md, "Frames and units"). Methods are safe to call from several
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

#include "monocle/types.h"

namespace monocle {

struct ClientError {
  enum class Code {
    kNoService,       // no monocled answered within the timeout (not running, other domain)
    kInvalidRequest,  // the service rejected the request: unknown camera, bad values, ...
    kFailed,          // the service could not do it: no frame, no board in view, no pose yet
    kDds,             // DDS itself failed (configuration, resources)
    kNotPermitted,    // this client's DDS Security permissions forbid it (e.g. a reader
                      // sending a floor calibration: that takes the operator role)
  };
  Code code = Code::kFailed;
  std::string message;  // a sentence a user can act on
};

MONOCLE_CLIENT_API std::ostream& operator<<(std::ostream& os, const ClientError& e);

// Camera namespaces claimed by more than one running monocled, in words ("" if none): their
// topics and requests would mix. Give each robot its own ros_namespace.
MONOCLE_CLIENT_API std::string DuplicateCameras(const std::vector<CameraStatus>& cameras);

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
    // A secured service (DDS Security): this client's identity directory of the keystore
    // `monocle security init` made (e.g. KEYSTORE/robot_ui). Empty: plain DDS.
    std::string security_dir{};
    // Called, in words, when data on a camera's topics was not taken as the camera's: a reply
    // or a calibration from a participant that does not serve the camera (spoofed, or a
    // second service misconfigured). Null: not reported. (subscribe_poses has its own.)
    // Called on the thread that made the request, inside it: it must not call the client.
    std::function<void(const std::string&)> on_ignored{};
  };

  static ClientResult<Client> open(Options options);
  static ClientResult<Client> open() { return open(Options{}); }
  ~Client();
  Client(Client&&) noexcept;
  Client& operator=(Client&&) noexcept;

  // `camera` is a camera's id ("sim-floor") or, where several robots share a domain, its ROS
  // namespace ("/robot1/monocle/front"); monocle status lists both.
  //
  // Floor pixels -> robot-frame points with 1-sigma, one result per pixel, in order (a bad
  // pixel is a result with its own error). `pixel_sigma_px` 0: the service's default 0.5 px.
  ClientResult<std::vector<MeasuredPoint>> measure(const std::string& camera,
                                                   const std::vector<PixelQuery>& pixels,
                                                   double pixel_sigma_px = 0);
  // The latest pose of a corner camera, or the pose of its next frame.
  ClientResult<Pose> pose(const std::string& camera, PoseWhich which = PoseWhich::kLatest);
  // Calibrates a floor camera from its next frame showing a chessboard lying on the floor
  // (cols x rows inner corners, squares of `square_m`); the service stores and publishes it,
  // and reports how good it is (`report`: where the board lay, the 1 sigma ahead, the
  // target's verdict, advice; the picture with options.overlay). A result that carries no
  // information, or whose height is outside 0.05-10 m (a square in the wrong unit?) unless
  // options.force, is an error and not stored.
  ClientResult<FloorCalibrationResult> calibrate_floor(const std::string& camera, int board_cols,
                                                       int board_rows, double square_m,
                                                       const FloorCalibrationOptions& options);
  ClientResult<FloorCalibrationResult> calibrate_floor(const std::string& camera, int board_cols,
                                                       int board_rows, double square_m);
  // The current status and calibration of every camera of every monocled on the domain.
  ClientResult<std::vector<CameraStatus>> status();
  ClientResult<std::vector<Calibration>> calibrations();

  // Every pose (of `camera`, or of all cameras when empty) as it is published, by the
  // service that serves the camera (the participant its status comes from). Poses on a
  // camera's topic from any other participant (spoofed, or a second service misconfigured),
  // and every pose of a camera two services claim, are not delivered: `on_ignored` says so,
  // in words, at most once a second per camera.
  ClientResult<Subscription> subscribe_poses(std::function<void(const Pose&)> on_pose,
                                             const std::string& camera,
                                             std::function<void(const std::string&)> on_ignored);
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
