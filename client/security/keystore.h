// A DDS Security keystore for one robot: a certificate authority, an identity (certificate and
// private key) for the service and for each named client, a governance document and, per
// identity, permissions by role, all signed by the CA (OMG DDS-Security 1.1, as Cyclone DDS's
// built-in plugins read them). Made with OpenSSL; no key material ever comes from the
// repository.
//
// Layout of DIR (each identity's directory is all a participant needs: mount just that one):
//   DIR/ca/ca_cert.pem, ca_key.pem   the CA (keep ca_key.pem off the robot when you can)
//   DIR/<name>/identity_ca.pem       the CA certificate (authenticates peers)
//   DIR/<name>/permissions_ca.pem    the same CA (signs governance and permissions)
//   DIR/<name>/governance.p7s        encrypted data, join access control, no unauthenticated
//   DIR/<name>/cert.pem, key.pem     this identity
//   DIR/<name>/permissions.p7s       what this identity may publish and subscribe
#pragma once

#include <string>
#include <vector>

#include "service/common/result.h"

namespace monocle::security {

enum class Role {
  kService,   // monocled: publishes its topics and replies, reads requests
  kReader,    // reads poses, status, calibrations; may query points and poses
  kOperator,  // a reader that may also send floor calibration commands
};

const char* RoleName(Role role);
// "reader" or "operator" (a client's role on the command line).
Result<Role> ParseClientRole(const std::string& text);

struct IdentitySpec {
  std::string name;  // a directory name and the certificate's CN: [A-Za-z0-9_.-]+
  Role role = Role::kReader;
};

// Creates DIR (or adds to it): the CA if DIR/ca does not hold one yet, then each identity
// that does not exist yet. An existing identity is never overwritten (an error names it).
// Certificates are valid from an hour ago for `valid_days`.
Status CreateKeystore(const std::string& dir, const std::vector<IdentitySpec>& identities,
                      int valid_days = 3650);

// The permissions document of one role (unsigned XML), for `subject` (the certificate's DN).
std::string PermissionsXml(const std::string& subject, Role role, const std::string& not_before,
                           const std::string& not_after);
std::string GovernanceXml();

}  // namespace monocle::security
