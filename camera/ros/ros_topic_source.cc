#include "camera/ros/ros_topic_source.h"

#include <cctype>
#include <sstream>

#include "camera/ros/image_sample.h"

namespace monocle {
namespace {

// ROS 2's topic name rules (design.ros2.org "Topic and Service name mapping"), absolute only:
// tokens of letters, digits and underscores, not starting with a digit, separated by one '/'.
bool IsAbsoluteRosName(const std::string& name) {
  if (name.size() < 2 || name.front() != '/' || name.back() == '/') return false;
  bool token_start = true;
  for (size_t i = 1; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '/') {
      if (token_start) return false;  // "//"
      token_start = true;
      continue;
    }
    const bool alnum = std::isalnum(static_cast<unsigned char>(c)) != 0;
    if (!alnum && c != '_') return false;
    if (token_start && std::isdigit(static_cast<unsigned char>(c))) return false;
    token_start = false;
  }
  return true;
}

std::optional<RosCameraInfo> CameraInfoOf(const sensor_msgs_msg_dds__CameraInfo_& info) {
  if (info.width == 0 || info.height == 0 || info.k[0] <= 0 || info.k[4] <= 0)
    return std::nullopt;  // an uncalibrated camera's info (all zero)
  RosCameraInfo out;
  out.frame_id = StringOf(info.header.frame_id);
  auto& k = out.intrinsics;
  k.width_px = static_cast<int>(info.width);
  k.height_px = static_cast<int>(info.height);
  k.fx = info.k[0];
  k.cx = info.k[2];
  k.fy = info.k[4];
  k.cy = info.k[5];
  // plumb_bob's k1 k2 p1 p2 k3 and rational_polynomial's eight are OpenCV's order.
  const std::string model = StringOf(info.distortion_model);
  if (model != "plumb_bob" && model != "rational_polynomial" && info.d._length > 0)
    return std::nullopt;
  for (uint32_t i = 0; i < info.d._length && i < k.distortion.size(); ++i)
    k.distortion[i] = info.d._buffer[i];
  return out;
}

}  // namespace

struct RosTopicSource::Readers {
  dds::Endpoint<sensor_msgs_msg_dds__Image_> image;
  dds::Endpoint<sensor_msgs_msg_dds__CameraInfo_> camera_info;
};

bool IsRosTopicDevice(const std::string& device) { return device.rfind(kRosDevicePrefix, 0) == 0; }

Result<std::string> RosTopicOfDevice(const std::string& device) {
  if (!IsRosTopicDevice(device))
    return MakeError(ErrorCode::kInvalidArgument, "'" + device + "' does not start with ros:");
  const std::string topic = device.substr(std::string(kRosDevicePrefix).size());
  if (!IsAbsoluteRosName(topic)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "'" + topic +
                         "' is not an absolute ROS 2 topic name: write it like "
                         "ros:/camera/image_raw (letters, digits and '_', separated by '/')");
  }
  return topic;
}

std::string SiblingCameraInfoTopic(const std::string& image_topic) {
  return image_topic.substr(0, image_topic.find_last_of('/')) + "/camera_info";
}

Result<std::unique_ptr<RosTopicSource>> RosTopicSource::Open(
    const std::shared_ptr<dds::Entity>& participant, const std::string& device,
    StateCallback on_state, std::chrono::milliseconds stall_timeout) {
  auto topic = RosTopicOfDevice(device);
  if (!topic) return topic.error();
  dds::EndpointQos newest_only;
  newest_only.best_effort = true;
  newest_only.history_depth = 1;  // a frame not yet taken is replaced by a newer one
  auto image = dds::Endpoint<sensor_msgs_msg_dds__Image_>::Open(
      participant, &sensor_msgs_msg_dds__Image__desc, ("rt" + *topic).c_str(), false, true,
      newest_only);
  if (!image) return image.error();
  const std::string info_topic = "rt" + SiblingCameraInfoTopic(*topic);
  auto info = dds::Endpoint<sensor_msgs_msg_dds__CameraInfo_>::Open(
      participant, &sensor_msgs_msg_dds__CameraInfo__desc, info_topic.c_str(), false, true,
      newest_only);
  if (!info) return info.error();
  std::unique_ptr<RosTopicSource> source(new RosTopicSource());
  source->device_ = device;
  source->topic_ = *topic;
  source->on_state_ = std::move(on_state);
  source->stall_timeout_ = stall_timeout;
  source->readers_ =
      std::make_shared<Readers>(Readers{std::move(image).value(), std::move(info).value()});
  source->SetState(SourceState::kReconnecting, "waiting for the first image on " + *topic);
  return source;
}

void RosTopicSource::SetState(SourceState state, const std::string& reason) {
  if (state == state_ && reason == last_reason_) return;
  state_ = state;
  last_reason_ = reason;
  if (on_state_) on_state_(state, reason);
}

void RosTopicSource::TakeCameraInfo() {
  auto infos = readers_->camera_info.Take<std::optional<RosCameraInfo>>(
      std::chrono::milliseconds(0),
      [](const sensor_msgs_msg_dds__CameraInfo_& info) { return CameraInfoOf(info); });
  if (!infos) return;
  for (auto& info : *infos) {
    if (info) camera_info_ = std::move(info);
  }
}

Result<Frame> RosTopicSource::Next(std::chrono::milliseconds timeout) {
  TakeCameraInfo();
  struct Taken {
    Result<cv::Mat> grey;
    int64_t stamp_ns;
    std::string frame_id;
  };
  auto taken = readers_->image.Take<Taken>(timeout, [](const sensor_msgs_msg_dds__Image_& image) {
    return Taken{GreyOfRosImage(ViewOf(image)), StampNs(image.header.stamp),
                 StringOf(image.header.frame_id)};
  });
  if (!taken) return taken.error();
  const auto now = std::chrono::steady_clock::now();
  if (taken->empty()) {
    if (now - last_image_ > stall_timeout_ && state_ == SourceState::kStreaming) {
      std::ostringstream why;
      why.precision(1);
      why << std::fixed << "no image on " << topic_ << " for "
          << std::chrono::duration<double>(now - last_image_).count()
          << " s: is the camera driver publishing?";
      SetState(SourceState::kReconnecting, why.str());
    }
    return MakeError(ErrorCode::kNotFound, "no image on " + topic_ + " yet");
  }
  Taken& newest = taken->back();
  last_image_ = now;
  if (!newest.grey) {
    // Not a permanent camera error: the driver may be reconfigured or replaced.
    const std::string why = topic_ + ": " + newest.grey.error().message;
    SetState(SourceState::kReconnecting, why);
    return MakeError(ErrorCode::kIo, why);
  }
  SetState(SourceState::kStreaming, "");
  Frame frame;
  frame.grey = std::move(newest.grey).value();
  frame.sequence = ++frames_;
  frame.capture_time_ns = newest.stamp_ns;
  frame.time_source = TimeSource::kHost;
  frame.frame_id = std::move(newest.frame_id);
  return frame;
}

}  // namespace monocle
