// monocle security init: a DDS Security keystore for a robot (client/security/keystore.h).
#include <filesystem>
#include <iostream>

#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "client/security/keystore.h"

namespace monocle::cli {
namespace {

constexpr const char* kSecurityHelp =
    R"(Usage: monocle security init DIR [--client NAME[:ROLE]]... [--service NAME] [--days N]

Makes a DDS Security keystore in DIR (or adds identities to one): a certificate authority
(DIR/ca), an identity for the service (DIR/monocled) and one per --client, each with the
CA certificate, the signed governance (every topic's discovery and data encrypted, only
participants with a certificate of this CA may join) and permissions by role:

  monocled  publishes its topics and replies, reads requests and other services' cameras
  reader    reads poses, status, calibrations; may query points and poses (the default)
  operator  a reader that may also send floor calibration commands

Keys are EC P-256, certificates and documents signed with SHA-256 (OpenSSL). Key files are
created readable by their owner only. Give each process only its own identity directory:

  monocled: security_dir: "DIR/monocled" in its configuration (or --security DIR/monocled)
  monocle:  --security DIR/NAME (or MONOCLE_SECURITY=DIR/NAME)
  library:  monocle::Client::Options::security_dir = "DIR/NAME"

DIR/ca/ca_key.pem signs new identities (run init again with more --client); keep it off
the robot. An existing identity is never overwritten.

  --client NAME[:ROLE]  a client identity; ROLE reader (default) or operator; repeatable
  --service NAME        the service's identity name (default monocled)
  --days N              validity of new certificates, days (default 3650)
)";

}  // namespace

int SecurityCommand(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kSecurityHelp;
    return kExitOk;
  }
  auto args = Args::Parse(argv, {{"--client", "--service", "--days"}, {}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto& pos = args->positionals();
  if (pos.size() != 2 || pos[0] != "init")
    return Fail("usage: monocle security init DIR [--client NAME[:ROLE]]... (see --help)",
                kExitUsage);
  const auto days = args->GetDouble("--days", 3650);
  if (!days || *days < 1 || *days > 36500 || *days != static_cast<int>(*days))
    return Fail("--days must be a whole number of days, 1..36500", kExitUsage);

  std::vector<security::IdentitySpec> identities;
  identities.push_back({args->Get("--service").value_or("monocled"), security::Role::kService});
  for (const auto& c : args->GetAll("--client")) {
    const auto colon = c.find(':');
    security::IdentitySpec spec{c.substr(0, colon), security::Role::kReader};
    if (colon != std::string::npos) {
      auto role = security::ParseClientRole(c.substr(colon + 1));
      if (!role) return Fail("--client " + c + ": " + role.error().message, kExitUsage);
      spec.role = *role;
    }
    identities.push_back(spec);
  }
  // When adding clients to an existing keystore, the service identity exists already.
  const std::string dir = pos[1];
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::path(dir) / identities[0].name, ec) &&
      !args->Has("--service"))
    identities.erase(identities.begin());
  if (auto made = security::CreateKeystore(dir, identities, static_cast<int>(*days)); !made)
    return Fail(made.error(), kExitFailure);
  for (const auto& id : identities)
    std::cout << dir << "/" << id.name << "  (" << security::RoleName(id.role) << ")\n";
  return kExitOk;
}

}  // namespace monocle::cli
