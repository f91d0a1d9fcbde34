#include "service/server/duplicate_watch.h"

#include <thread>

#include "idl/protocol/convert.h"
#include "idl/protocol/wire.h"

namespace monocle {
namespace {

// A service that serves (or tries to serve) a camera; a stopped one has left, a failed one
// has refused or given up.
bool Serving(CameraState state) {
  return state == CameraState::kStreaming || state == CameraState::kReconnecting;
}

}  // namespace

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

std::map<std::string, std::string> DuplicateWatch::WaitForServed(
    std::chrono::milliseconds wait, const std::function<bool()>& stop_requested) {
  // The newest state of each (namespace, service) seen.
  std::map<std::pair<std::string, std::string>, CameraState> latest;
  const auto deadline = std::chrono::steady_clock::now() + wait;
  while (std::chrono::steady_clock::now() < deadline && !stop_requested()) {
    auto taken = statuses_->Take<CameraStatus>(
        std::chrono::milliseconds(50),
        [](const monocle_msgs_msg_dds__CameraStatus_& s) { return wire::FromSample(s); });
    if (!taken) continue;
    for (const auto& s : *taken) {
      if (s.service != own_ && namespaces_.count(s.ros_namespace) > 0)
        latest[{s.ros_namespace, s.service}] = s.state;
    }
  }
  std::map<std::string, std::string> served;
  for (const auto& [key, state] : latest) {
    if (!Serving(state)) continue;
    served[key.first] = key.second;
    reported_.emplace(key, 0);  // the refusal says it; NewClashes need not say it again
  }
  return served;
}

std::vector<DuplicateWatch::Clash> DuplicateWatch::NewClashes() {
  std::vector<Clash> out;
  for (;;) {
    auto taken = statuses_->Take<std::pair<CameraStatus, dds_instance_handle_t>>(
        std::chrono::milliseconds(0),
        [](const monocle_msgs_msg_dds__CameraStatus_& s, const dds_sample_info_t& info) {
          return std::make_pair(wire::FromSample(s), info.publication_handle);
        });
    if (!taken || taken->empty()) return out;
    for (const auto& [s, writer] : *taken) {
      if (s.service == own_ || namespaces_.count(s.ros_namespace) == 0 ||
          s.state == CameraState::kStopped)
        continue;
      if (!reported_.emplace(std::make_pair(s.ros_namespace, s.service), writer).second) continue;
      if (s.state == CameraState::kFailed) {
        // The newcomer refused it (or failed on its own): we keep serving; say who tried.
        out.push_back({s.ros_namespace, "monocled " + s.service + " also claims camera namespace " +
                                            s.ros_namespace + " (camera '" + s.camera_id +
                                            "'); this service keeps serving it (" + s.last_error +
                                            ")"});
        continue;
      }
      out.push_back(
          {s.ros_namespace, "camera namespace " + s.ros_namespace + " (camera '" + s.camera_id +
                                "') is also served by monocled " + s.service +
                                " on this DDS domain: give each robot its own ros_namespace "
                                "(see service/README.md, \"Several robots on one domain\")"});
    }
  }
}

std::vector<std::string> DuplicateWatch::ClashesOver() {
  std::set<std::string> left, staying;
  for (auto it = reported_.begin(); it != reported_.end();) {
    const auto& [key, writer] = *it;
    dds_builtintopic_endpoint_t* still =
        writer != 0 ? dds_get_matched_publication_data(statuses_->reader(), writer) : nullptr;
    if (still != nullptr) dds_builtintopic_free_endpoint(still);
    if (writer != 0 && still == nullptr) {
      left.insert(key.first);
      it = reported_.erase(it);  // heard again, it is reported again
    } else {
      staying.insert(key.first);
      ++it;
    }
  }
  std::vector<std::string> out;
  for (const std::string& ns : left)
    if (staying.count(ns) == 0) out.push_back(ns);
  return out;
}

}  // namespace monocle
