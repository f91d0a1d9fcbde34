// The corner pipeline's options from the command line, written once for `corner locate` and
// `replay`: --map, --mount, --prior, --level-sigma and --detect-every, checked alike.
#pragma once

#include <string>

#include "client/cli/args.h"
#include "service/common/result.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle::cli {

// --level-sigma DEG: how level the robot stands (1 sigma), radians; 0.3 degrees by default.
Result<double> LevelSigmaRad(const Args& args);

// --map MAP --mount MOUNT [--prior X,Y,HEADING_DEG]: poses in a room map, solved at the map's
// ceiling less the mount's height. --mount alone: the pose combined with the robot's level.
// Neither: a bare pipeline (the caller sets the ceiling distance).
Result<CornerPipelineOptions> CornerSetupFromArgs(const Args& args, double level_sigma_rad);

// --detect-every N: a full detection at least every N frames (default 30); `unit` names the
// frames in the message ("images", "frames").
Result<int> DetectEvery(const Args& args, const std::string& unit);

// A mistake on the command line (an error whose message names an option) exits with 2, any
// other failure (a file that does not load) with 1.
int UsageOrFailure(const Error& error);

}  // namespace monocle::cli
