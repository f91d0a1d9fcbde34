// Notices another monocled on the DDS domain serving one of our camera namespaces: its
// requests and topics would mix with ours, and clients could not tell the two apart. Reads
// /monocle/cameras (every service's camera status) and reports each clash once.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "client/protocol/dds.h"
#include "idl/monocle_msgs.h"

namespace monocle {

class DuplicateWatch {
 public:
  static Result<std::unique_ptr<DuplicateWatch>> Open(
      const std::shared_ptr<dds::Entity>& participant, std::string own_service_id,
      std::vector<std::string> own_namespaces);

  // Statuses received since the last call; returns a message for each new clash.
  std::vector<std::string> NewClashes();

 private:
  DuplicateWatch() = default;
  std::string own_;
  std::set<std::string> namespaces_;
  std::set<std::pair<std::string, std::string>> reported_;  // (namespace, other service)
  std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>> statuses_;
};

}  // namespace monocle
