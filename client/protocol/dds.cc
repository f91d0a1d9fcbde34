#include "client/protocol/dds.h"

namespace monocle::dds {

Error DdsError(const std::string& what, dds_return_t rc) {
  return MakeError(ErrorCode::kIo,
                   what + ": " + dds_strretcode(rc) +
                       " (is CYCLONEDDS_URI valid? see docker/cyclonedds-loopback.xml)");
}

}  // namespace monocle::dds

namespace monocle::dds {

Result<std::shared_ptr<Entity>> CreateParticipant(dds_domainid_t domain) {
  auto participant = std::make_shared<Entity>(dds_create_participant(domain, nullptr, nullptr));
  if (participant->get() < 0)
    return DdsError("cannot create a DDS participant", participant->get());
  return participant;
}

}  // namespace monocle::dds
