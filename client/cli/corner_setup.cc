#include "client/cli/corner_setup.h"

#include <memory>
#include <numbers>

#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {

void DeclareCornerSetup(CommandLine& line, CornerArgs* a, const std::string& frames) {
  line.Text("--mount", &a->mount_path, "MOUNT.pbtxt",
            "the camera's pose on the robot base (a CameraMount, e.g. "
            "idl/examples/camera_mount.pbtxt; its z is the optical centre's height above the "
            "floor). With --map: each corner's ceiling distance follows from the map. Alone: "
            "the robot stands level, which fixes the camera's tilt and swing; they are combined "
            "with the image's (client/cli/GUIDE.md, \"On a robot: the mount's level\")");
  line.Number("--level-sigma", &a->level_sigma_deg, "DEG",
              "how level the robot stands: 1 sigma about each horizontal axis (the floor's "
              "slope, the suspension, the mount's own error), with --mount",
              In("degrees").Between(0.01, 5));
  line.Whole("--detect-every", &a->detect_every, "N",
             "a full detection at least every N " + frames + " while tracking",
             In(frames).AtLeast(1));
  line.Text("--map", &a->map_path, "MAP.pbtxt",
            "the rooms and their ceiling corners (idl/room_map.proto, service/README.md "
            "\"Room map\"); needs --mount. Every corner is tried and the one consistent with the "
            "view is named, with the base's x, y (metres) and heading (degrees from the map's "
            "+x towards +y) in the map frame and their 1 sigma. Several corners fit: "
            "\"ambiguous\" with every candidate; none is guessed");
  line.Custom("--prior", "X,Y,HEADING_DEG",
              "where the robot is in the map (metres, degrees), with --map: decides between "
              "look-alike corners; while tracking only the first " +
                  frames.substr(0, frames.size() - 1) +
                  "'s, after which each located pose is the next one's prior",
              [a](const std::string& text) -> std::optional<std::string> {
                const auto v = ParseNumberList(text);
                if (!v || v->size() != 3)
                  return "'" + text + "' is not X,Y,HEADING_DEG (metres, degrees)";
                a->prior = BasePose2d{(*v)[0], (*v)[1], (*v)[2] * std::numbers::pi / 180};
                return std::nullopt;
              });
}

void DeclareCeilingDistance(CommandLine& line, CornerArgs* a, const std::string& instead) {
  line.Number("--ceiling-distance", &a->ceiling_distance_m, "Z",
              "camera optical centre to ceiling; " + instead, In("metres").Above(0));
}

Result<CornerPipelineOptions> CornerSetupFrom(const CornerArgs& a) {
  CornerPipelineOptions options;
  options.level_sigma_rad = a.level_sigma_deg * std::numbers::pi / 180;
  options.tracking.detect_every_n_frames = a.detect_every;
  if (!a.map_path) {
    if (a.prior) return MakeError(ErrorCode::kInvalidArgument, "--prior needs --map MAP.pbtxt");
    if (a.mount_path) {
      // The camera rides a robot on a level floor, which fixes its tilt and swing.
      auto mount = LoadCameraMountFile(*a.mount_path, RoomMap{});
      if (!mount) return mount.error();
      options.base_camera = *mount;
    }
    return options;
  }
  if (!a.mount_path) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--map needs --mount MOUNT.pbtxt: the camera's pose on the robot base "
                     "(e.g. idl/examples/camera_mount.pbtxt)");
  }
  if (a.ceiling_distance_m) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--ceiling-distance is not used with --map: each corner's follows from the "
                     "map's ceiling height and the mount's height");
  }
  auto map = LoadRoomMapFile(*a.map_path);
  if (!map) return map.error();
  auto mount = LoadCameraMountFile(*a.mount_path, *map);
  if (!mount) return mount.error();
  // Each corner's ceiling distance follows from the mount: solve at any one of them (the map
  // scales the pose to each corner's).
  options.ceiling_distance_m = map->rooms.front().ceiling_height_m - mount->translation.z();
  options.base_camera = *mount;
  options.room_map = std::make_shared<const RoomMap>(std::move(*map));
  options.initial_pose = a.prior;
  return options;
}

Result<double> CeilingDistanceM(const CornerArgs& a, std::optional<double> from_calibration,
                                const std::string& calibration_path, const std::string& also) {
  if (a.ceiling_distance_m) return *a.ceiling_distance_m;
  if (from_calibration && *from_calibration > 0) return *from_calibration;
  return MakeError(ErrorCode::kInvalidArgument,
                   "the camera-to-ceiling distance is unknown: give --ceiling-distance Z (metres) "
                   "or add corner { ceiling_distance: Z } to " +
                       calibration_path + also);
}

int UsageOrFailure(const Error& error) {
  return error.code == ErrorCode::kInvalidArgument && error.message.starts_with("--")
             ? kExitUsage
             : kExitFailure;
}

}  // namespace monocle::cli
