// Frames from a ROS 2 image topic (a camera configured as device "ros:/camera/image_raw"): a
// robot's own camera driver keeps the device, monocled reads what it publishes. The reader is
// best effort, so it matches publishers with ROS 2's default QoS (reliable) and with its
// sensor-data QoS alike; it keeps only the newest frame. The sibling camera_info topic
// (image_transport's convention: /camera/camera_info beside /camera/image_raw) is read too.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "camera/frame_source.h"
#include "camera/source_state.h"
#include "idl/protocol/dds.h"
#include "service/geometry/camera_model.h"

namespace monocle {

// The device prefix that names an image topic instead of a camera.
inline constexpr const char* kRosDevicePrefix = "ros:";
bool IsRosTopicDevice(const std::string& device);
// The topic a "ros:" device names, checked against ROS 2's rules for an absolute topic name;
// the error says what a valid one looks like.
Result<std::string> RosTopicOfDevice(const std::string& device);
// image_transport's camera_info topic beside an image topic.
std::string SiblingCameraInfoTopic(const std::string& image_topic);

// The last sensor_msgs/CameraInfo read (plumb_bob or rational_polynomial distortion).
struct RosCameraInfo {
  CameraIntrinsics intrinsics;
  std::string frame_id;
};

class RosTopicSource : public FrameSource {
 public:
  using StateCallback = std::function<void(SourceState, const std::string& reason)>;

  // Readers on `participant` for the device's topic and its camera_info. `on_state` hears
  // "reconnecting" while no image has come for `stall_timeout`, "streaming" when one comes.
  static Result<std::unique_ptr<RosTopicSource>> Open(
      const std::shared_ptr<dds::Entity>& participant, const std::string& device,
      StateCallback on_state, std::chrono::milliseconds stall_timeout);

  const std::string& id() const override { return device_; }
  // The newest image as grey (its stamp as capture time, its frame_id carried), or kNotFound
  // when none came within `timeout`, or kInvalidArgument for an image monocle cannot read
  // (reported once; the next good image streams again). Never permanent: a driver restarts.
  Result<Frame> Next(std::chrono::milliseconds timeout) override;
  // The camera_info last received, if any.
  const std::optional<RosCameraInfo>& camera_info() const { return camera_info_; }
  std::optional<CameraIntrinsics> intrinsics() const override {
    if (!camera_info_) return std::nullopt;
    return camera_info_->intrinsics;
  }
  const std::string& topic() const { return topic_; }

 private:
  RosTopicSource() = default;
  void SetState(SourceState state, const std::string& reason);
  void TakeCameraInfo();

  std::string device_, topic_;
  StateCallback on_state_;
  std::chrono::milliseconds stall_timeout_{1000};
  struct Readers;
  std::shared_ptr<Readers> readers_;
  std::optional<RosCameraInfo> camera_info_;
  SourceState state_ = SourceState::kReconnecting;
  std::string last_reason_;
  uint64_t frames_ = 0;
  std::chrono::steady_clock::time_point last_image_ = std::chrono::steady_clock::now();
};

}  // namespace monocle
