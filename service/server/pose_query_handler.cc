#include "service/server/pose_query_handler.h"

#include <iostream>

namespace monocle {

Result<std::unique_ptr<PoseQueryHandler>> PoseQueryHandler::Start(
    const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras) {
  std::unique_ptr<PoseQueryHandler> h(new PoseQueryHandler());
  auto server = Server::Start(
      participant, CamerasWith(cameras, &CameraSetup::corner),
      &monocle_msgs_srv_dds__GetPose_Request__desc, &monocle_msgs_srv_dds__GetPose_Response__desc,
      wire::kGetPose, &PoseQueryHandler::Parse,
      [self = h.get()](Server::Incoming&& in) { self->Answer(std::move(in)); },
      // Never blocks: the latest pose is copied, a wait for the next frame is queued.
      [](uint32_t) { return true; }, [self = h.get()] { self->ExpireWaiting(); });
  if (!server) return server.error();
  h->server_ = std::move(server).value();
  return h;
}

uint32_t PoseQueryHandler::Parse(const monocle_msgs_srv_dds__GetPose_Request_& request) {
  return wire::EnumValue(request.which);  // any value a client sent, checked by InvalidWhich
}

std::string PoseQueryHandler::InvalidWhich(uint32_t which) {
  if (which == monocle_msgs_msg_dds__POSE_LATEST || which == monocle_msgs_msg_dds__POSE_NEXT_FRAME)
    return "";
  return "which must be POSE_LATEST (0) or POSE_NEXT_FRAME (1), not " + std::to_string(which);
}

Pose PoseQueryHandler::NoPose(const CameraSetup& camera) {
  Pose empty;
  empty.camera_id = camera.id;
  empty.frame_id = camera.ros_parent_frame;
  return empty;
}

void PoseQueryHandler::ReplyInto(monocle_msgs_msg_dds__RequestStatus status,
                                 const std::string& error, const Pose& pose,
                                 monocle_msgs_srv_dds__GetPose_Response_* reply) {
  *reply = {};
  reply->status = status;
  reply->error = const_cast<char*>(error.c_str());
  wire::ToSample(pose, &reply->pose);
}

void PoseQueryHandler::Reply(const Server::Incoming& in, monocle_msgs_msg_dds__RequestStatus status,
                             const std::string& error, const Pose* pose) {
  const Pose empty = NoPose(*in.camera);
  monocle_msgs_srv_dds__GetPose_Response_ reply;
  ReplyInto(status, error, pose != nullptr ? *pose : empty, &reply);
  if (auto s = in.server->SendReply(reply, in.header); !s)
    std::cerr << "monocled: " << s.error() << "\n";
}

void PoseQueryHandler::Answer(Server::Incoming&& in) {
  const std::string& camera = in.camera->id;
  if (const std::string invalid = InvalidWhich(in.value); !invalid.empty()) {
    Reply(in, monocle_msgs_msg_dds__REQUEST_INVALID, invalid, nullptr);
    return;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  if (in.value == monocle_msgs_msg_dds__POSE_NEXT_FRAME) {
    waiting_.push_back({std::move(in), std::chrono::steady_clock::now() + kFrameWait});
    return;
  }
  const auto it = latest_.find(camera);
  if (it == latest_.end()) {
    lock.unlock();
    Reply(in, monocle_msgs_msg_dds__REQUEST_FAILED,
          "no pose yet from camera '" + camera + "' (see monocle status)", nullptr);
    return;
  }
  const Pose pose = it->second;
  lock.unlock();
  Reply(in, monocle_msgs_msg_dds__REQUEST_OK, "", &pose);
}

void PoseQueryHandler::OnPose(const Pose& pose) {
  std::vector<Pending> ready;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_.insert_or_assign(pose.camera_id, pose);
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      if (it->request.camera->id == pose.camera_id) {
        ready.push_back(std::move(*it));
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const auto& p : ready) Reply(p.request, monocle_msgs_msg_dds__REQUEST_OK, "", &pose);
}

void PoseQueryHandler::ExpireWaiting() {
  std::vector<Pending> expired;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      if (it->deadline < now) {
        expired.push_back(std::move(*it));
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const auto& e : expired) {
    Reply(e.request, monocle_msgs_msg_dds__REQUEST_FAILED,
          "no frame from camera '" + e.request.camera->id + "' within " +
              std::to_string(kFrameWait.count() / 1000) + " s (see monocle status)",
          nullptr);
  }
}

}  // namespace monocle
