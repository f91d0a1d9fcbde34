// Base trajectory files: the robot base's poses in the map frame, one per line,
// "x_m y_m heading_deg" (spaces or commas; '#' starts a comment; heading from the map's +x
// towards +y). Used by `monocle render room`, `monocle simcam --scene room` and
// `monocle map draw` as ground truth. Every error names the line, e.g.
// "drive.txt: line 4: heading_deg 'east' is not a number".
// (The corner scene's trajectories are corner poses: camera/sim/sim_gv_camera.h.)
#pragma once

#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/map_pose.h"

namespace monocle {

Result<std::vector<BasePose2d>> ParseBaseTrajectory(const std::string& text,
                                                    const std::string& source);
Result<std::vector<BasePose2d>> LoadBaseTrajectoryFile(const std::string& path);

}  // namespace monocle
