#include "idl/protocol/dds.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace monocle::dds {

Error DdsError(const std::string& what, dds_return_t rc) {
  if (rc == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
    return MakeError(ErrorCode::kPermissionDenied,
                     what + ": not allowed by this identity's DDS Security permissions");
  }
  return MakeError(ErrorCode::kIo,
                   what + ": " + dds_strretcode(rc) +
                       " (is CYCLONEDDS_URI valid? see docker/cyclonedds-loopback.xml)");
}

namespace {

// The files of one identity (client/security/keystore.h) and the DDS Security property each
// one goes to.
struct SecurityFile {
  const char* name;
  const char* property;
};
constexpr SecurityFile kSecurityFiles[] = {
    {"identity_ca.pem", "dds.sec.auth.identity_ca"},
    {"cert.pem", "dds.sec.auth.identity_certificate"},
    {"key.pem", "dds.sec.auth.private_key"},
    {"permissions_ca.pem", "dds.sec.access.permissions_ca"},
    {"governance.p7s", "dds.sec.access.governance"},
    {"permissions.p7s", "dds.sec.access.permissions"},
};

}  // namespace

Status CheckSecurityDirectory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return MakeError(ErrorCode::kNotFound,
                     "security directory " + dir +
                         " does not exist (make one with `monocle security init DIR`)");
  for (const auto& f : kSecurityFiles) {
    const fs::path path = fs::path(dir) / f.name;
    if (!fs::is_regular_file(path, ec))
      return MakeError(ErrorCode::kNotFound,
                       "security directory " + dir + " has no " + f.name +
                           ": give one identity's directory of a keystore made by `monocle "
                           "security init` (e.g. KEYSTORE/monocled)");
  }
  return Ok{};
}

std::optional<std::vector<dds_instance_handle_t>> MatchedPublications(dds_entity_t reader) {
  std::vector<dds_instance_handle_t> handles(64);
  for (;;) {
    const dds_return_t n = dds_get_matched_publications(reader, handles.data(), handles.size());
    if (n < 0) return std::nullopt;
    if (static_cast<size_t>(n) <= handles.size()) {
      handles.resize(static_cast<size_t>(n));
      std::sort(handles.begin(), handles.end());
      return handles;
    }
    handles.resize(static_cast<size_t>(n) + 16);  // more matched meanwhile: ask again
  }
}

bool UsesSecurity(dds_entity_t participant) {
  dds_qos_t* qos = dds_create_qos();
  char* value = nullptr;
  const bool secure = dds_get_qos(participant, qos) == DDS_RETCODE_OK &&
                      dds_qget_prop(qos, "dds.sec.auth.library.path", &value);
  dds_free(value);
  dds_delete_qos(qos);
  return secure;
}

Result<std::shared_ptr<Entity>> CreateParticipant(dds_domainid_t domain,
                                                  const std::string& security_dir,
                                                  size_t max_sample_bytes) {
  if (!security_dir.empty()) {
    if (auto c = CheckSecurityDirectory(security_dir); !c) return c.error();
  }
  dds_entity_t owned_domain = 0;
  if (max_sample_bytes > 0) {
    // The user's configuration (CYCLONEDDS_URI, a list of files and XML) first, ours last:
    // Cyclone applies them in order, so only MaxSampleSize is overridden.
    std::string config;
    if (const char* uri = std::getenv("CYCLONEDDS_URI"); uri != nullptr && *uri != '\0')
      config = std::string(uri) + ",";
    config += "<CycloneDDS><Domain id=\"any\"><Internal><MaxSampleSize>" +
              std::to_string(max_sample_bytes) +
              "B</MaxSampleSize></Internal></Domain></CycloneDDS>";
    owned_domain = dds_create_domain(domain, config.c_str());
    if (owned_domain < 0)
      return DdsError("cannot create DDS domain " + std::to_string(domain), owned_domain);
  }
  dds_qos_t* qos = nullptr;
  if (!security_dir.empty()) {
    const std::string abs = std::filesystem::absolute(security_dir).lexically_normal().string();
    qos = dds_create_qos();
    // The plugins by their default names: Debian's libddsc finds them in its private
    // directory. Setting any dds.sec. property makes Cyclone require all of them.
    dds_qset_prop(qos, "dds.sec.auth.library.path", "dds_security_auth");
    dds_qset_prop(qos, "dds.sec.auth.library.init", "init_authentication");
    dds_qset_prop(qos, "dds.sec.auth.library.finalize", "finalize_authentication");
    dds_qset_prop(qos, "dds.sec.crypto.library.path", "dds_security_crypto");
    dds_qset_prop(qos, "dds.sec.crypto.library.init", "init_crypto");
    dds_qset_prop(qos, "dds.sec.crypto.library.finalize", "finalize_crypto");
    dds_qset_prop(qos, "dds.sec.access.library.path", "dds_security_ac");
    dds_qset_prop(qos, "dds.sec.access.library.init", "init_access_control");
    dds_qset_prop(qos, "dds.sec.access.library.finalize", "finalize_access_control");
    for (const auto& f : kSecurityFiles)
      dds_qset_prop(qos, f.property, ("file:" + abs + "/" + f.name).c_str());
  }
  const dds_entity_t handle = dds_create_participant(domain, qos, nullptr);
  auto participant = std::make_shared<Entity>(handle, handle > 0 ? owned_domain : 0);
  if (handle <= 0 && owned_domain > 0) dds_delete(owned_domain);
  if (qos != nullptr) dds_delete_qos(qos);
  if (participant->get() < 0) {
    if (!security_dir.empty()) {
      return MakeError(ErrorCode::kInvalidArgument,
                       std::string("cannot join DDS domain with the identity in ") + security_dir +
                           ": " + dds_strretcode(participant->get()) +
                           " (an expired or foreign certificate, or governance and permissions "
                           "not signed by its CA; Cyclone's log says which)");
    }
    return DdsError("cannot create a DDS participant", participant->get());
  }
  return participant;
}

}  // namespace monocle::dds
