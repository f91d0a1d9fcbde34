// One small interface for every frame source (Aravis devices real or simulated, files).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"

namespace monocle {

enum class TimeSource {
  kHost,    // the host's clock when the frame was received (no PTP)
  kCamera,  // the camera's clock (PTP-synchronised)
};

struct Frame {
  cv::Mat grey;                 // 8-bit grey; may view the source's buffer (see `keepalive`)
  uint64_t sequence = 0;        // the camera's frame id
  int64_t capture_time_ns = 0;  // see time_source
  TimeSource time_source = TimeSource::kHost;
  int64_t device_time_ns = 0;  // the camera's own timestamp, in its clock
  std::string camera_id;
  std::string frame_id;  // the source's name of its optical frame (a ROS image's); may be empty
  // Holds the source's buffer while the frame lives; releasing it returns the buffer.
  std::shared_ptr<void> keepalive;
};

// The frame's capture time in seconds, for motion models; unset when the source gave none.
inline std::optional<double> CaptureTimeS(const Frame& frame) {
  if (frame.capture_time_ns == 0) return std::nullopt;
  return 1e-9 * static_cast<double>(frame.capture_time_ns);
}

// The one rule for camera errors. A configuration the camera cannot take (a GenICam feature
// it does not have, a value outside its range, a pixel format it does not offer) will not
// heal by waiting: it is permanent, reported once, and the camera's state is "failed". Every
// other error (camera not found yet, lost, stalled, I/O) is retried with back-off.
inline bool IsPermanentCameraError(const Error& error) {
  return error.code == ErrorCode::kInvalidArgument || error.code == ErrorCode::kOutOfRange;
}

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const std::string& id() const = 0;
  // The next frame, or an error: kNotFound when nothing arrived within `timeout`
  // (a stalled stream), kIo when the camera was lost.
  virtual Result<Frame> Next(std::chrono::milliseconds timeout) = 0;
  // The intrinsics the source itself publishes (a ROS driver's camera_info), if any.
  virtual std::optional<CameraIntrinsics> intrinsics() const { return std::nullopt; }
};

}  // namespace monocle
