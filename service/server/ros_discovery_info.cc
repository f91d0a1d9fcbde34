#include "service/server/ros_discovery_info.h"

#include <cstring>

#include "idl/ros2_messages.h"

namespace monocle {
namespace {

bool IsRosTopic(const char* name) {
  return name != nullptr &&
         (std::strncmp(name, "rt/", 3) == 0 || std::strncmp(name, "rq/", 3) == 0 ||
          std::strncmp(name, "rr/", 3) == 0);
}

bool SameGuid(const dds_guid_t& a, const dds_guid_t& b) {
  return std::memcmp(a.v, b.v, sizeof(a.v)) == 0;
}

// The endpoints of `participant` that a built-in topic lists now.
Status CollectEndpoints(dds_entity_t participant, dds_entity_t builtin_topic, const dds_guid_t& own,
                        std::vector<dds_guid_t>* out) {
  const dds::Entity reader(dds_create_reader(participant, builtin_topic, nullptr, nullptr));
  if (reader.get() < 0) return dds::DdsError("cannot read DDS's built-in topics", reader.get());
  // Every endpoint of the domain seen from here, far above what one service has (64 cameras).
  constexpr size_t kMost = 8192;
  std::vector<void*> samples(kMost, nullptr);
  std::vector<dds_sample_info_t> infos(kMost);
  const dds_return_t n = dds_read(reader.get(), samples.data(), infos.data(), kMost, kMost);
  if (n < 0) return dds::DdsError("cannot read DDS's built-in topics", n);
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
    if (SameGuid(e->participant_key, own) && IsRosTopic(e->topic_name)) out->push_back(e->key);
  }
  dds_return_loan(reader.get(), samples.data(), n);
  return Ok{};
}

// The message in a Gid layout of `bytes`, written by `writer`.
template <typename Participant, typename Node, typename Gid, size_t kBytes>
Status WriteInfo(dds_entity_t writer, const RosGraphEntities& entities) {
  static_assert(sizeof(Gid::data) == kBytes && kBytes >= sizeof(dds_guid_t::v));
  auto gids = [](const std::vector<dds_guid_t>& guids) {
    std::vector<Gid> out(guids.size());
    for (size_t i = 0; i < guids.size(); ++i) {
      std::memset(out[i].data, 0, kBytes);
      std::memcpy(out[i].data, guids[i].v, sizeof(guids[i].v));
    }
    return out;
  };
  std::vector<Gid> readers = gids(entities.readers), writers = gids(entities.writers);
  Node node{};
  std::strncpy(node.node_namespace, kRosNodeNamespace, sizeof(node.node_namespace) - 1);
  std::strncpy(node.node_name, kRosNodeName, sizeof(node.node_name) - 1);
  node.reader_gid_seq._length = node.reader_gid_seq._maximum =
      static_cast<uint32_t>(readers.size());
  node.reader_gid_seq._buffer = readers.data();
  node.writer_gid_seq._length = node.writer_gid_seq._maximum =
      static_cast<uint32_t>(writers.size());
  node.writer_gid_seq._buffer = writers.data();
  Participant info{};
  std::memcpy(info.gid.data, entities.participant.v, sizeof(entities.participant.v));
  info.node_entities_info_seq._length = info.node_entities_info_seq._maximum = 1;
  info.node_entities_info_seq._buffer = &node;
  if (const dds_return_t rc = dds_write(writer, &info); rc < 0)
    return dds::DdsError("cannot publish ros_discovery_info", rc);
  return Ok{};
}

// Humble's message under rmw_dds_common's type name, without the type information idlc
// made for monocle_humble's (a ROS reader registers none and matches by name).
const dds_topic_descriptor_t* HumbleDescriptor() {
  const dds_topic_descriptor_t& d =
      monocle_humble_rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc;
  static const dds_topic_descriptor_t humble = {
      d.m_size,
      d.m_align,
      d.m_flagset & ~static_cast<uint32_t>(DDS_TOPIC_XTYPES_METADATA),
      d.m_nkeys,
      rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc.m_typename,
      d.m_keys,
      d.m_nops,
      d.m_ops,
      d.m_meta,
      {},
      {},
      d.restrict_data_representation};
  return &humble;
}

}  // namespace

Result<RosGraphEntities> RosEndpointsOf(dds_entity_t participant) {
  RosGraphEntities out;
  if (const dds_return_t rc = dds_get_guid(participant, &out.participant); rc < 0)
    return dds::DdsError("cannot get the participant's GUID", rc);
  if (auto s = CollectEndpoints(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, out.participant,
                                &out.writers);
      !s)
    return s.error();
  if (auto s = CollectEndpoints(participant, DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, out.participant,
                                &out.readers);
      !s)
    return s.error();
  return out;
}

Result<std::unique_ptr<RosDiscoveryInfo>> RosDiscoveryInfo::Publish(
    const std::shared_ptr<dds::Entity>& participant, RosDiscoveryLayout layout) {
  std::unique_ptr<RosDiscoveryInfo> info(new RosDiscoveryInfo());
  info->participant_ = participant;
  const dds_entity_t p = participant->get();
  const bool humble = layout == RosDiscoveryLayout::kHumble;
  info->topic_ = dds::Entity(dds_create_topic(
      p, humble ? HumbleDescriptor() : &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc,
      kRosDiscoveryTopic, nullptr, nullptr));
  if (info->topic_.get() < 0)
    return dds::DdsError("cannot create topic ros_discovery_info", info->topic_.get());
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  info->writer_ = dds::Entity(dds_create_writer(p, info->topic_.get(), qos, nullptr));
  dds_delete_qos(qos);
  if (info->writer_.get() < 0)
    return dds::DdsError("cannot create the ros_discovery_info writer", info->writer_.get());
  auto entities = RosEndpointsOf(p);
  if (!entities) return entities.error();
  info->readers_ = entities->readers.size();
  info->writers_ = entities->writers.size();
  const Status written =
      humble
          ? WriteInfo<monocle_humble_rmw_dds_common_msg_dds__ParticipantEntitiesInfo_,
                      monocle_humble_rmw_dds_common_msg_dds__NodeEntitiesInfo_,
                      monocle_humble_rmw_dds_common_msg_dds__Gid_, 24>(info->writer_.get(),
                                                                       *entities)
          : WriteInfo<rmw_dds_common_msg_dds__ParticipantEntitiesInfo_,
                      rmw_dds_common_msg_dds__NodeEntitiesInfo_, rmw_dds_common_msg_dds__Gid_, 16>(
                info->writer_.get(), *entities);
  if (!written) return written.error();
  return info;
}

}  // namespace monocle
