// The corner pipeline's options from the command line, declared once for `corner locate`,
// `replay` and `corner fit-mount`: --map, --mount, --prior, --level-sigma, --detect-every
// and --ceiling-distance, checked alike.
#pragma once

#include <optional>
#include <string>

#include "client/cli/command_line.h"
#include "service/common/result.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle::cli {

struct CornerArgs {
  std::optional<std::string> map_path, mount_path;
  std::optional<BasePose2d> prior;  // metres, radians
  double level_sigma_deg = 0.3;
  int detect_every = 30;
  std::optional<double> ceiling_distance_m;
};

// --map, --mount, --prior, --level-sigma and --detect-every (`frames`: what the command
// calls its frames, "images" or "frames").
void DeclareCornerSetup(CommandLine& line, CornerArgs* args, const std::string& frames);
// --ceiling-distance Z: `instead` says what it overrides.
void DeclareCeilingDistance(CommandLine& line, CornerArgs* args, const std::string& instead);

// --map MAP --mount MOUNT [--prior X,Y,HEADING_DEG]: poses in a room map, solved at the map's
// ceiling less the mount's height. --mount alone: the pose combined with the robot's level.
// Neither: a bare pipeline (the caller sets the ceiling distance). A file that does not load
// is an error of kind other than kInvalidArgument.
Result<CornerPipelineOptions> CornerSetupFrom(const CornerArgs& args);

// The camera-to-ceiling distance, metres: --ceiling-distance Z, else `from_calibration` (the
// calibration file's corner { ceiling_distance }). The error says both ways to give it, and
// `also` after them.
Result<double> CeilingDistanceM(const CornerArgs& args, std::optional<double> from_calibration,
                                const std::string& calibration_path, const std::string& also = "");

// A mistake on the command line (an error whose message names an option) exits with 2, any
// other failure (a file that does not load) with 1.
int UsageOrFailure(const Error& error);

}  // namespace monocle::cli
