// The command line's live forms (--camera ID): errors of the client and poses as JSON.
#pragma once

#include <optional>

#include "idl/cli_output.pb.h"
#include "monocle/client.h"

namespace monocle::cli {

// Prints the client's error; exit status 1.
int Fail(const ClientError& error);

// The JSON form of a pose from the service (the offline form's fields inside camera,
// sequence, capture time).
proto::LivePoseOutput ToLiveOutput(const Pose& pose);

}  // namespace monocle::cli
