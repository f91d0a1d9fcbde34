// The command line's live forms (--camera ID): a monocle::Client from --domain and --timeout.
#pragma once

#include <optional>

#include "client/cli/args.h"
#include "idl/cli_output.pb.h"
#include "monocle/client.h"

namespace monocle::cli {

// --domain D (default 0) and --timeout S (seconds, default `default_timeout_s`). On a bad value
// prints the error and sets *exit_status.
std::optional<Client> OpenClient(const Args& args, int* exit_status, double default_timeout_s = 10);

// Prints the client's error; exit status 1.
int Fail(const ClientError& error);

// The JSON form of a pose from the service (the offline form's fields inside camera,
// sequence, capture time).
proto::LivePoseOutput ToLiveOutput(const Pose& pose);

}  // namespace monocle::cli
