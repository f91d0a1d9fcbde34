#include "client/cli/corner_setup.h"

#include <cmath>
#include <memory>
#include <numbers>

#include "client/cli/commands.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {

Result<double> LevelSigmaRad(const Args& args) {
  const auto deg = args.GetDouble("--level-sigma", 0.3);
  if (!deg || !(*deg >= 0.01 && *deg <= 5))
    return MakeError(ErrorCode::kInvalidArgument,
                     "--level-sigma must be how level the robot stands, 1 sigma in degrees "
                     "(0.01-5; default 0.3)");
  return *deg * std::numbers::pi / 180;
}

namespace {

Result<std::optional<BasePose2d>> Prior(const Args& args) {
  const auto text = args.Get("--prior");
  if (!text) return std::optional<BasePose2d>();
  const auto v = ParseNumberList(*text);
  if (!v || v->size() != 3) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--prior '" + *text + "' is not X,Y,HEADING_DEG (metres, degrees)");
  }
  return std::optional<BasePose2d>(BasePose2d{(*v)[0], (*v)[1], (*v)[2] * std::numbers::pi / 180});
}

}  // namespace

Result<CornerPipelineOptions> CornerSetupFromArgs(const Args& args, double level_sigma_rad) {
  CornerPipelineOptions options;
  options.level_sigma_rad = level_sigma_rad;
  const auto map_path = args.Get("--map");
  const auto mount_path = args.Get("--mount");
  if (!map_path) {
    if (args.Get("--prior"))
      return MakeError(ErrorCode::kInvalidArgument, "--prior needs --map MAP.pbtxt");
    if (mount_path) {
      // The camera rides a robot on a level floor, which fixes its tilt and swing.
      auto mount = LoadCameraMountFile(*mount_path, RoomMap{});
      if (!mount) return mount.error();
      options.base_camera = *mount;
    }
    return options;
  }
  if (!mount_path) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--map needs --mount MOUNT.pbtxt: the camera's pose on the robot base "
                     "(e.g. idl/examples/camera_mount.pbtxt)");
  }
  if (args.Get("--ceiling-distance")) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--ceiling-distance is not used with --map: each corner's follows from the "
                     "map's ceiling height and the mount's height");
  }
  auto map = LoadRoomMapFile(*map_path);
  if (!map) return map.error();
  auto mount = LoadCameraMountFile(*mount_path, *map);
  if (!mount) return mount.error();
  auto prior = Prior(args);
  if (!prior) return prior.error();
  // Each corner's ceiling distance follows from the mount: solve at any one of them (the map
  // scales the pose to each corner's).
  options.ceiling_distance_m = map->rooms.front().ceiling_height_m - mount->translation.z();
  options.base_camera = *mount;
  options.room_map = std::make_shared<const RoomMap>(std::move(*map));
  options.initial_pose = *prior;
  return options;
}

Result<int> DetectEvery(const Args& args, const std::string& unit) {
  const auto n = args.GetDouble("--detect-every", 30);
  if (!n || *n < 1 || *n != std::floor(*n) || *n > 1e6)
    return MakeError(ErrorCode::kInvalidArgument,
                     "--detect-every must be a whole number of " + unit + " >= 1");
  return static_cast<int>(*n);
}

int UsageOrFailure(const Error& error) {
  return error.code == ErrorCode::kInvalidArgument && error.message.starts_with("--")
             ? kExitUsage
             : kExitFailure;
}

}  // namespace monocle::cli
