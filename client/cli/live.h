// The command line's live forms (--camera ID): errors of the client and poses as JSON.
#pragma once

#include <optional>

#include "idl/cli_output.pb.h"
#include "monocle/client.h"
#include "service/common/result.h"

namespace monocle::cli {

// Prints the client's error; exit status 1.
int Fail(const ClientError& error);

// The service's camera named `name` (its id or ROS namespace), looked up on the cameras'
// directory at once rather than waited for: an unknown name, or a camera whose role is not
// `role` ("corner" or "floor"; empty: any), is an error that lists the cameras there are.
Result<CameraStatus> FindServiceCamera(Client& client, const std::string& name, int domain,
                                       const std::string& role = "");

// The JSON form of a pose from the service (the offline form's fields inside camera,
// sequence, capture time).
proto::LivePoseOutput ToLiveOutput(const Pose& pose);

}  // namespace monocle::cli
