#include "service/server/duplicate_watch.h"

#include "client/protocol/convert.h"
#include "client/protocol/wire.h"

namespace monocle {

Result<std::unique_ptr<DuplicateWatch>> DuplicateWatch::Open(
    const std::shared_ptr<dds::Entity>& participant, std::string own_service_id,
    std::vector<std::string> own_namespaces) {
  std::unique_ptr<DuplicateWatch> w(new DuplicateWatch());
  w->own_ = std::move(own_service_id);
  w->namespaces_.insert(own_namespaces.begin(), own_namespaces.end());
  auto reader = dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>::Open(
      participant, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic, false, true,
      wire::kDirectoryReaderQos);
  if (!reader) return reader.error();
  w->statuses_ = std::make_unique<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>>(
      std::move(reader).value());
  return w;
}

std::vector<std::string> DuplicateWatch::NewClashes() {
  std::vector<std::string> out;
  for (;;) {
    auto taken = statuses_->Take<CameraStatus>(
        std::chrono::milliseconds(0),
        [](const monocle_msgs_msg_dds__CameraStatus_& s) { return wire::FromSample(s); });
    if (!taken || taken->empty()) return out;
    for (const auto& s : *taken) {
      if (s.service == own_ || namespaces_.count(s.ros_namespace) == 0 ||
          s.state == CameraState::kStopped)
        continue;
      if (!reported_.insert({s.ros_namespace, s.service}).second) continue;
      out.push_back("camera namespace " + s.ros_namespace + " (camera '" + s.camera_id +
                    "') is also served by monocled " + s.service +
                    " on this DDS domain: give each robot its own ros_namespace "
                    "(see README, \"Several robots on one domain\")");
    }
  }
}

}  // namespace monocle
