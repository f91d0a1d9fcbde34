// monocle map check | draw: a room map file validated and explained, or drawn from above with
// a trajectory and the poses `corner locate --map` found.
#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/map_picture.h"
#include "service/io/base_trajectory_file.h"
#include "service/io/bounded_file.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {
namespace {

constexpr const char* kOverview = R"(Usage: monocle map check|draw ...

  check MAP.pbtxt [--mount MOUNT.pbtxt]
      Validates a room map (and a camera mount against it) and lists its rooms and corners.
  draw MAP.pbtxt --out MAP.png [--trajectory FILE] [--poses POSES.jsonl]
      The map from above with a trajectory and the poses `corner locate --map` found.

service/README.md, "Room map" explains the files (examples in idl/examples/).
)";

constexpr const char* kCheckAbout =
    R"text(Reads a room map (idl/room_map.proto, text format) as `corner locate --map` and monocled do,
and says what it holds: each room's outline, floor area and ceiling height, and each ceiling
corner a camera can locate itself by (listed in the file, or every right-angle vertex with
the room inside it) with the headings of its X and Y ceiling edges (degrees from the map's +x
towards +y). With --mount, the camera's height and each corner's ceiling distance from it.)text";

constexpr const char* kCheckFooter =
    R"text(An error names the line and the field, e.g. "map.pbtxt: line 12: room[0].corner[1].position
is not a vertex of room[0].outline (the nearest is 0.80 m away)". Exit status 1 then.)text";

std::string Degrees(const Eigen::Vector2d& direction) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(0)
     << std::atan2(direction.y(), direction.x()) * 180 / std::numbers::pi;
  return os.str();
}

int Check(const std::vector<std::string>& argv) {
  std::vector<std::string> file;
  std::optional<std::string> mount_path;
  CommandLine line("map check", kCheckAbout);
  line.Footer(kCheckFooter);
  line.Positionals("MAP.pbtxt", &file, "the room map", 1, 1);
  line.Text("--mount", &mount_path, "MOUNT.pbtxt", "the camera's pose on the robot base");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const std::string& path = file[0];
  const auto map = LoadRoomMapFile(path);
  if (!map) return Fail(map.error(), kExitFailure);
  std::optional<RigidTransform> mount;
  if (mount_path) {
    auto m = LoadCameraMountFile(*mount_path, *map);
    if (!m) return Fail(m.error(), kExitFailure);
    mount = *m;
  }
  std::cout << std::fixed << path << ": " << map->rooms.size()
            << (map->rooms.size() == 1 ? " room" : " rooms") << "\n";
  for (const auto& room : map->rooms) {
    std::cout << "  room " << room.id << ": " << room.outline_m.size() << " walls, floor "
              << std::setprecision(2) << SignedDoubleArea(room.outline_m) / 2 << " m², ceiling "
              << room.ceiling_height_m << " m, " << room.corners.size()
              << (room.corners.size() == 1 ? " corner" : " corners") << "\n";
    for (const auto& c : room.corners) {
      std::cout << "    corner " << c.id << " at (" << std::setprecision(2) << c.position_m.x()
                << ", " << c.position_m.y() << ") m, edges X " << Degrees(c.x_edge) << " deg, Y "
                << Degrees(c.y_edge) << " deg";
      if (mount) {
        std::cout << ", ceiling distance " << std::setprecision(2)
                  << c.ceiling_height_m - mount->translation.z() << " m";
      }
      std::cout << "\n";
    }
  }
  if (mount) {
    std::cout << "  camera " << std::setprecision(2) << mount->translation.z()
              << " m above the floor, " << mount->translation.x() << " m ahead of and "
              << mount->translation.y() << " m left of the base origin\n";
  }
  std::cout << "ok\n";
  return kExitOk;
}

// The "map" objects of `corner locate --map --json` lines; a broken line is named.
Result<std::vector<proto::MapLocationOutput>> ReadPoses(const std::string& path) {
  auto text = ReadBoundedFile(path, "poses", kMaxTextFileBytes);
  if (!text) return text.error();
  std::vector<proto::MapLocationOutput> out;
  std::istringstream in(*text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    proto::CornerOutput pose;
    google::protobuf::util::JsonParseOptions options;
    options.ignore_unknown_fields = false;
    if (const auto status = google::protobuf::util::JsonStringToMessage(line, &pose, options);
        !status.ok()) {
      return MakeError(ErrorCode::kInvalidArgument,
                       path + ": line " + std::to_string(number) +
                           ": not a line of `monocle corner locate --map --json`: " +
                           std::string(status.message()));
    }
    if (pose.has_map()) out.push_back(pose.map());
  }
  return out;
}

int Draw(const std::vector<std::string>& argv) {
  std::vector<std::string> file;
  std::string out;
  std::optional<std::string> trajectory_path, poses_path;
  CommandLine line("map draw",
                   "Draws the map from above (map frame: x right, y up, metres, a 1 m grid): "
                   "rooms, walls, each\nceiling corner with its X and Y edges, and optionally "
                   "the robot's path and the poses located.");
  line.Positionals("MAP.pbtxt", &file, "the room map", 1, 1);
  line.Text("--out", &out, "MAP.png", "the picture (.png, .jpg or .pgm)");
  line.Require("--out");
  line.Text("--trajectory", &trajectory_path, "FILE",
            "the robot's true path (x_m y_m heading_deg a line, as `render room --trajectory` "
            "takes), in black");
  line.Text("--poses", &poses_path, "POSES.jsonl",
            "the output of `corner locate --map --json`: each located pose as a dot in the "
            "colour of the corner it was measured from, joined to that corner, with its "
            "heading; candidates of undecided views as grey rings");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto map = LoadRoomMapFile(file[0]);
  if (!map) return Fail(map.error(), kExitFailure);
  MapPicture picture;
  picture.map = &*map;
  picture.title = std::filesystem::path(file[0]).filename().string();
  if (const auto& path = trajectory_path) {
    auto trajectory = LoadBaseTrajectoryFile(*path);
    if (!trajectory) return Fail(trajectory.error(), kExitFailure);
    picture.trajectory = std::move(*trajectory);
  }
  if (const auto& path = poses_path) {
    auto poses = ReadPoses(*path);
    if (!poses) return Fail(poses.error(), kExitFailure);
    picture.poses = std::move(*poses);
    picture.title += " with " + std::filesystem::path(*path).filename().string();
  }
  if (auto written = WriteImage(out, DrawMapPicture(picture)); !written)
    return Fail(written.error(), kExitFailure);
  return kExitOk;
}

}  // namespace

int MapCommand(const std::vector<std::string>& argv) {
  if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
    (argv.empty() ? std::cerr : std::cout) << kOverview;
    return argv.empty() ? kExitUsage : kExitOk;
  }
  const std::vector<std::string> rest(argv.begin() + 1, argv.end());
  if (argv[0] == "check") return Check(rest);
  if (argv[0] == "draw") return Draw(rest);
  return Fail("unknown map command '" + argv[0] + "' (check, draw)", kExitUsage);
}

}  // namespace monocle::cli
