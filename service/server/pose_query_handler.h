// Answers <corner camera namespace>/get_pose (monocle_msgs/srv/GetPose): the latest pose of
// the camera at once, or the pose of its next processed frame when that comes (or a failure
// after kFrameWait).
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "idl/protocol/convert.h"
#include "service/server/request_server.h"

namespace monocle {

class PoseQueryHandler {
 public:
  static constexpr std::chrono::milliseconds kFrameWait{5000};

  static Result<std::unique_ptr<PoseQueryHandler>> Start(
      const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras);

  // Every pose of a processed frame (from the camera's processing thread).
  void OnPose(const Pose& pose);

  // What the handler does with a request, without DDS (the fuzz target drives these): the
  // request's `which`, why it is invalid ("" when it is not), and the reply (the pose sent
  // with a failure is NoPose). The reply points into `error` and `pose`.
  static uint32_t Parse(const monocle_msgs_srv_dds__GetPose_Request_& request);
  static std::string InvalidWhich(uint32_t which);
  static Pose NoPose(const CameraSetup& camera);
  static void ReplyInto(monocle_msgs_msg_dds__RequestStatus status, const std::string& error,
                        const Pose& pose, monocle_msgs_srv_dds__GetPose_Response_* reply);

 private:
  using Server = RequestServer<monocle_msgs_srv_dds__GetPose_Request_,
                               monocle_msgs_srv_dds__GetPose_Response_, uint32_t>;
  struct Pending {
    Server::Incoming request;
    std::chrono::steady_clock::time_point deadline;
  };

  PoseQueryHandler() = default;
  void Answer(Server::Incoming&& in);
  void ExpireWaiting();
  static void Reply(const Server::Incoming& in, monocle_msgs_msg_dds__RequestStatus status,
                    const std::string& error, const Pose* pose);

  std::mutex mutex_;
  std::map<std::string, Pose> latest_;  // by camera id
  std::vector<Pending> waiting_;        // for the next frame
  std::unique_ptr<Server> server_;      // last: its thread stops first
};

}  // namespace monocle
