#include "service/server/dds.h"

namespace monocle::dds {

Error DdsError(const std::string& what, dds_return_t rc) {
  return MakeError(ErrorCode::kIo,
                   what + ": " + dds_strretcode(rc) +
                       " (is CYCLONEDDS_URI valid? see docker/cyclonedds-loopback.xml)");
}

}  // namespace monocle::dds
