// monocle security init: a DDS Security keystore for a robot (client/security/keystore.h).
#include <filesystem>
#include <iostream>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/security/keystore.h"

namespace monocle::cli {
namespace {

constexpr const char* kSecurityAbout =
    R"(Makes a DDS Security keystore in DIR (or adds identities to one): a certificate authority
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
the robot. An existing identity is never overwritten.)";

}  // namespace

int SecurityCommand(const std::vector<std::string>& argv) {
  std::vector<std::string> dir_arg;
  std::optional<std::string> service;
  int days = 3650;
  std::vector<security::IdentitySpec> clients;
  CommandLine line("security init", kSecurityAbout);
  line.Positionals("DIR", &dir_arg, "the keystore's folder", 1, 1);
  line.CustomRepeated("--client", "NAME[:ROLE]",
                      "a client identity; ROLE reader (default) or operator",
                      [&clients](const std::string& c) -> std::optional<std::string> {
                        const auto colon = c.find(':');
                        security::IdentitySpec spec{c.substr(0, colon), security::Role::kReader};
                        if (colon != std::string::npos) {
                          auto role = security::ParseClientRole(c.substr(colon + 1));
                          if (!role) return c + ": " + role.error().message;
                          spec.role = *role;
                        }
                        clients.push_back(spec);
                        return std::nullopt;
                      });
  line.Text("--service", &service, "NAME", "the service's identity name (default monocled)");
  line.Whole("--days", &days, "N", "validity of new certificates", In("days").Between(1, 36500));
  if (argv.empty() || argv[0] != "init") {
    if (!argv.empty() && (argv[0] == "--help" || argv[0] == "-h")) {
      std::cout << line.Help();
      return kExitOk;
    }
    return Fail("security takes a command: init (see monocle security init --help)", kExitUsage);
  }
  if (const auto exit_now = line.Parse({argv.begin() + 1, argv.end()})) return *exit_now;
  std::vector<security::IdentitySpec> identities;
  identities.push_back({service.value_or("monocled"), security::Role::kService});
  identities.insert(identities.end(), clients.begin(), clients.end());
  // When adding clients to an existing keystore, the service identity exists already.
  const std::string& dir = dir_arg[0];
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::path(dir) / identities[0].name, ec) && !service)
    identities.erase(identities.begin());
  if (auto made = security::CreateKeystore(dir, identities, days); !made)
    return Fail(made.error(), kExitFailure);
  for (const auto& id : identities)
    std::cout << dir << "/" << id.name << "  (" << security::RoleName(id.role) << ")\n";
  return kExitOk;
}

}  // namespace monocle::cli
