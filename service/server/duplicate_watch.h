// Another monocled on the DDS domain serving one of our camera namespaces: its requests and
// topics would mix with ours, and clients could not tell the two apart. Reads
// /monocle/cameras (every service's camera status, transient-local, so a newcomer learns at
// once what is already served).
//
// The rule: a service starting finds out what is already served (WaitForServed) and refuses
// those namespaces itself (state "failed", saying who serves them). Two services that start
// within the same discovery wait both serve; each then reports the clash (NewClashes) in its
// log and status, and clients refuse to use the namespace until one is stopped.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "idl/monocle_msgs.h"
#include "idl/protocol/dds.h"

namespace monocle {

class DuplicateWatch {
 public:
  static Result<std::unique_ptr<DuplicateWatch>> Open(
      const std::shared_ptr<dds::Entity>& participant, std::string own_service_id,
      std::vector<std::string> own_namespaces);

  // Reads statuses for `wait` (discovery of the services already on the domain), or until
  // `stop_requested`. Returns our namespaces another live service serves: namespace -> its
  // service id.
  std::map<std::string, std::string> WaitForServed(std::chrono::milliseconds wait,
                                                   const std::function<bool()>& stop_requested);

  struct Clash {
    std::string ros_namespace;
    std::string message;  // for the log and the camera's status
  };
  // Statuses received since the last call; one Clash for each newly seen other service on
  // one of our namespaces (serving it, or having refused it because we serve it).
  std::vector<Clash> NewClashes();
  // Our namespaces whose every other claimant reported by NewClashes has left the domain (its
  // status writer is gone) since the last call: their clash is over.
  std::vector<std::string> ClashesOver();

 private:
  DuplicateWatch() = default;
  std::string own_;
  std::set<std::string> namespaces_;
  // (namespace, other service) reported, and the status writer it was heard from.
  std::map<std::pair<std::string, std::string>, dds_instance_handle_t> reported_;
  std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>> statuses_;
};

}  // namespace monocle
