// monocled in ROS 2's graph: what rmw_dds_common's GraphCache reads to answer `ros2 node list`
// and `ros2 node info`. One ParticipantEntitiesInfo on the DDS topic ros_discovery_info
// (reliable, transient-local, keep-last 1, as rmw_cyclonedds_cpp writes it): the participant's
// Gid, and one node, /monocled, with the Gids of every ROS endpoint of the participant (its
// rt/, rq/ and rr/ readers and writers). A Gid is the entity's DDS GUID, as rmw_cyclonedds_cpp
// makes it; Humble's is 24 bytes (the GUID, then zeros), Iron's and later 16.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "idl/protocol/dds.h"
#include "service/common/result.h"
#include "service/server/service_config.h"

namespace monocle {

inline constexpr const char* kRosDiscoveryTopic = "ros_discovery_info";
inline constexpr const char* kRosNodeName = "monocled";
inline constexpr const char* kRosNodeNamespace = "/";

struct RosGraphEntities {
  dds_guid_t participant{};
  std::vector<dds_guid_t> readers, writers;  // ROS endpoints only (rt/, rq/, rr/)
};

// The ROS endpoints `participant` has now, from Cyclone's built-in topics (they list the
// participant's own readers and writers too).
Result<RosGraphEntities> RosEndpointsOf(dds_entity_t participant);

class RosDiscoveryInfo {
 public:
  // Publishes the participant's endpoints as they are now (call once all are created); the
  // writer keeps the sample for late joiners until the service ends.
  static Result<std::unique_ptr<RosDiscoveryInfo>> Publish(
      const std::shared_ptr<dds::Entity>& participant, RosDiscoveryLayout layout);

  size_t readers() const { return readers_; }
  size_t writers() const { return writers_; }

 private:
  RosDiscoveryInfo() = default;
  dds::Entity topic_, writer_;
  std::shared_ptr<dds::Entity> participant_;
  size_t readers_ = 0, writers_ = 0;
};

}  // namespace monocle
