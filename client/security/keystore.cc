#include "client/security/keystore.h"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace monocle::security {
namespace {

namespace fs = std::filesystem;

// One owner per OpenSSL handle.
struct FreeKey {
  void operator()(EVP_PKEY* p) const { EVP_PKEY_free(p); }
};
struct FreeCert {
  void operator()(X509* p) const { X509_free(p); }
};
struct FreeBio {
  void operator()(BIO* p) const { BIO_free(p); }
};
struct FreePkcs7 {
  void operator()(PKCS7* p) const { PKCS7_free(p); }
};
struct FreeExtension {
  void operator()(X509_EXTENSION* p) const { X509_EXTENSION_free(p); }
};
using Key = std::unique_ptr<EVP_PKEY, FreeKey>;
using Cert = std::unique_ptr<X509, FreeCert>;
using Bio = std::unique_ptr<BIO, FreeBio>;
using Pkcs7 = std::unique_ptr<PKCS7, FreePkcs7>;
using Extension = std::unique_ptr<X509_EXTENSION, FreeExtension>;

constexpr const char* kOrganisation = "monocle";

Error OpenSslError(const std::string& what) {
  std::string detail;
  while (const unsigned long code = ERR_get_error()) {
    char buf[256];
    ERR_error_string_n(code, buf, sizeof buf);
    detail += std::string(detail.empty() ? "" : "; ") + buf;
  }
  return MakeError(ErrorCode::kIo, what + (detail.empty() ? "" : ": " + detail));
}

std::string BioText(BIO* bio) {
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio, &data);
  return n > 0 ? std::string(data, static_cast<size_t>(n)) : std::string();
}

Result<Key> NewKey() {
  // EC prime256v1: what DDS Security's built-in authentication signs with (ECDSA-SHA256).
  Key key(EVP_EC_gen("P-256"));
  if (!key) return OpenSslError("cannot make an EC P-256 key");
  return key;
}

Status AddExtension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  Extension ext(X509V3_EXT_conf_nid(nullptr, &ctx, nid, value));
  if (!ext || X509_add_ext(cert, ext.get(), -1) != 1)
    return OpenSslError(std::string("cannot add the extension ") + value);
  return Ok{};
}

// A certificate for `cn` with `key`, signed by `issuer_key` (self-signed when `issuer` is
// null).
Result<Cert> NewCertificate(const std::string& cn, EVP_PKEY* key, X509* issuer,
                            EVP_PKEY* issuer_key, bool is_ca, int valid_days) {
  Cert cert(X509_new());
  if (!cert) return OpenSslError("cannot make a certificate");
  X509_set_version(cert.get(), 2);  // v3: extensions
  unsigned char serial_bytes[8];
  if (RAND_bytes(serial_bytes, sizeof serial_bytes) != 1) return OpenSslError("no random bytes");
  uint64_t serial = 0;
  for (unsigned char b : serial_bytes) serial = (serial << 8) | b;
  ASN1_INTEGER_set_uint64(X509_get_serialNumber(cert.get()), serial >> 1);  // positive
  // From an hour ago: a peer whose clock is a little behind still accepts it.
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), -3600);
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), static_cast<long>(valid_days) * 86400);
  X509_NAME* name = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>(kOrganisation), -1, -1, 0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>(cn.c_str()), -1, -1, 0);
  X509_set_issuer_name(cert.get(), issuer != nullptr ? X509_get_subject_name(issuer) : name);
  if (X509_set_pubkey(cert.get(), key) != 1) return OpenSslError("cannot set a public key");
  X509* signer = issuer != nullptr ? issuer : cert.get();
  if (is_ca) {
    if (auto s = AddExtension(cert.get(), signer, NID_basic_constraints, "critical,CA:TRUE"); !s)
      return s.error();
    if (auto s = AddExtension(cert.get(), signer, NID_key_usage,
                              "critical,keyCertSign,cRLSign,digitalSignature");
        !s)
      return s.error();
  } else {
    if (auto s = AddExtension(cert.get(), signer, NID_basic_constraints, "critical,CA:FALSE"); !s)
      return s.error();
    if (auto s = AddExtension(cert.get(), signer, NID_key_usage, "critical,digitalSignature"); !s)
      return s.error();
  }
  if (auto s = AddExtension(cert.get(), signer, NID_subject_key_identifier, "hash"); !s)
    return s.error();
  if (X509_sign(cert.get(), issuer_key, EVP_sha256()) <= 0)
    return OpenSslError("cannot sign the certificate of " + cn);
  return cert;
}

std::string CertPem(X509* cert) {
  Bio out(BIO_new(BIO_s_mem()));
  PEM_write_bio_X509(out.get(), cert);
  return BioText(out.get());
}

std::string KeyPem(EVP_PKEY* key) {
  Bio out(BIO_new(BIO_s_mem()));
  PEM_write_bio_PrivateKey(out.get(), key, nullptr, nullptr, 0, nullptr, nullptr);
  return BioText(out.get());
}

// The DN as DDS-Security permissions name it; Cyclone's access control compares it with the
// identity certificate's subject.
std::string SubjectName(X509* cert) {
  char* line = X509_NAME_oneline(X509_get_subject_name(cert), nullptr, 0);
  std::string s = line != nullptr ? line : "";
  OPENSSL_free(line);
  return s;
}

// S/MIME, clear text with a detached signature: what `openssl smime -sign -text` writes and
// what Cyclone's access control verifies against the permissions CA.
Result<std::string> SignSmime(const std::string& text, X509* ca, EVP_PKEY* ca_key) {
  Bio data(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  constexpr int kFlags = PKCS7_DETACHED | PKCS7_STREAM | PKCS7_TEXT;
  Pkcs7 signed_data(PKCS7_sign(ca, ca_key, nullptr, data.get(), kFlags));
  if (!signed_data) return OpenSslError("cannot sign a security document");
  Bio out(BIO_new(BIO_s_mem()));
  if (SMIME_write_PKCS7(out.get(), signed_data.get(), data.get(), kFlags) != 1)
    return OpenSslError("cannot write a signed security document");
  return BioText(out.get());
}

Status WriteFile(const fs::path& path, const std::string& text, bool secret) {
  // Secrets are created private (0600) before any byte is written.
  const mode_t old = umask(secret ? 077 : 022);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  umask(old);
  if (!out) return MakeError(ErrorCode::kIo, "cannot write " + path.string());
  return Ok{};
}

Result<std::string> ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return MakeError(ErrorCode::kNotFound, "cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string XmlTime(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

bool ValidName(const std::string& name) {
  if (name.empty() || name.size() > 64 || name == "ca" || name == "." || name == "..") return false;
  return std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
  });
}

std::string TopicList(const std::vector<std::string>& topics) {
  std::string s;
  for (const auto& t : topics) s += "<topic>" + t + "</topic>";
  return s;
}

}  // namespace

const char* RoleName(Role role) {
  switch (role) {
    case Role::kService:
      return "service";
    case Role::kReader:
      return "reader";
    case Role::kOperator:
      return "operator";
  }
  return "?";
}

Result<Role> ParseClientRole(const std::string& text) {
  if (text == "reader") return Role::kReader;
  if (text == "operator") return Role::kOperator;
  return MakeError(ErrorCode::kInvalidArgument,
                   "unknown role '" + text + "': a client is a reader or an operator");
}

std::string GovernanceXml() {
  // Every topic: discovery and data encrypted, readers and writers checked against the
  // permissions; no participant without a certificate of this CA joins at all.
  return R"(<?xml version="1.0" encoding="utf-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
}

std::string PermissionsXml(const std::string& subject, Role role, const std::string& not_before,
                           const std::string& not_after) {
  // DDS topic names (wire.h): rt/ topics, rq/ requests and rr/ replies of the ROS 2 services.
  std::vector<std::string> publish, subscribe;
  switch (role) {
    case Role::kService:
      // ros_discovery_info: ROS 2's graph (`ros2 node list`), not under rt/.
      publish = {"rt/*", "rr/*", "ros_discovery_info"};
      subscribe = {"rq/*", "rt/monocle/cameras"};  // others' cameras: duplicate names
      break;
    case Role::kOperator:
      publish = {"rq/*/calibrate_floorRequest"};
      [[fallthrough]];
    case Role::kReader:
      publish.push_back("rq/*/measure_pointsRequest");
      publish.push_back("rq/*/get_poseRequest");
      subscribe = {"rt/*", "rr/*", "ros_discovery_info"};
      break;
  }
  std::ostringstream x;
  x << R"(<?xml version="1.0" encoding="utf-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="monocle_)"
    << RoleName(role) << R"(">
      <subject_name>)"
    << subject << R"(</subject_name>
      <validity><not_before>)"
    << not_before << "</not_before><not_after>" << not_after << R"(</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        <publish><topics>)"
    << TopicList(publish) << R"(</topics></publish>
        <subscribe><topics>)"
    << TopicList(subscribe) << R"(</topics></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)";
  return x.str();
}

Status CreateKeystore(const std::string& dir, const std::vector<IdentitySpec>& identities,
                      int valid_days) {
  for (const auto& id : identities) {
    if (!ValidName(id.name))
      return MakeError(ErrorCode::kInvalidArgument,
                       "identity name '" + id.name.substr(0, 64) +
                           "' must be 1-64 of A-Z a-z 0-9 _ . - (and not 'ca')");
    if (fs::exists(fs::path(dir) / id.name))
      return MakeError(ErrorCode::kInvalidArgument,
                       (fs::path(dir) / id.name).string() +
                           " exists already; remove it to make that identity anew");
  }
  std::error_code ec;
  const fs::path ca_dir = fs::path(dir) / "ca";
  fs::create_directories(ca_dir, ec);
  if (ec)
    return MakeError(ErrorCode::kIo, "cannot create " + ca_dir.string() + ": " + ec.message());
  fs::permissions(ca_dir, fs::perms::owner_all, ec);

  Key ca_key;
  Cert ca_cert;
  if (fs::exists(ca_dir / "ca_key.pem")) {
    // Adding identities to an existing keystore: the CA signs them too.
    auto key_pem = ReadText(ca_dir / "ca_key.pem");
    auto cert_pem = ReadText(ca_dir / "ca_cert.pem");
    if (!key_pem) return key_pem.error();
    if (!cert_pem) return cert_pem.error();
    Bio kb(BIO_new_mem_buf(key_pem->data(), static_cast<int>(key_pem->size())));
    Bio cb(BIO_new_mem_buf(cert_pem->data(), static_cast<int>(cert_pem->size())));
    ca_key.reset(PEM_read_bio_PrivateKey(kb.get(), nullptr, nullptr, nullptr));
    ca_cert.reset(PEM_read_bio_X509(cb.get(), nullptr, nullptr, nullptr));
    if (!ca_key || !ca_cert) return OpenSslError("cannot read the CA in " + ca_dir.string());
  } else {
    auto key = NewKey();
    if (!key) return key.error();
    auto cert = NewCertificate("monocle CA", key->get(), nullptr, key->get(), true, valid_days);
    if (!cert) return cert.error();
    ca_key = std::move(key).value();
    ca_cert = std::move(cert).value();
    if (auto w = WriteFile(ca_dir / "ca_key.pem", KeyPem(ca_key.get()), true); !w) return w;
    if (auto w = WriteFile(ca_dir / "ca_cert.pem", CertPem(ca_cert.get()), false); !w) return w;
  }
  auto governance = SignSmime(GovernanceXml(), ca_cert.get(), ca_key.get());
  if (!governance) return governance.error();
  const std::time_t now = std::time(nullptr);
  const std::string not_before = XmlTime(now - 3600);
  const std::string not_after = XmlTime(now + static_cast<std::time_t>(valid_days) * 86400);

  for (const auto& id : identities) {
    const fs::path out = fs::path(dir) / id.name;
    fs::create_directories(out, ec);
    if (ec) return MakeError(ErrorCode::kIo, "cannot create " + out.string() + ": " + ec.message());
    fs::permissions(out, fs::perms::owner_all, ec);
    auto key = NewKey();
    if (!key) return key.error();
    auto cert = NewCertificate(id.name, key->get(), ca_cert.get(), ca_key.get(), false, valid_days);
    if (!cert) return cert.error();
    auto permissions =
        SignSmime(PermissionsXml(SubjectName(cert->get()), id.role, not_before, not_after),
                  ca_cert.get(), ca_key.get());
    if (!permissions) return permissions.error();
    const std::string ca_pem = CertPem(ca_cert.get());
    for (const auto& [file, text, secret] :
         {std::tuple{"identity_ca.pem", ca_pem, false},
          {"permissions_ca.pem", ca_pem, false},
          {"governance.p7s", *governance, false},
          {"cert.pem", CertPem(cert->get()), false},
          {"key.pem", KeyPem(key->get()), true},
          {"permissions.p7s", *permissions, false},
          {"role", std::string(RoleName(id.role)) + "\n", false}}) {
      if (auto w = WriteFile(out / file, text, secret); !w) return w;
    }
  }
  return Ok{};
}

}  // namespace monocle::security
