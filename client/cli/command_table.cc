#include "client/cli/command_table.h"

#include <algorithm>
#include <iostream>
#include <set>
#include <sstream>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"

namespace monocle::cli {

const std::vector<CommandEntry>& Commands() {
  static const std::vector<CommandEntry> commands = {
      {"Measuring from images and calibration files:", "intrinsics calibrate",
       "Focal lengths, principal point and lens distortion from several board images."},
      {"", "intrinsics import",
       "A calibration another tool wrote (ROS camera_info YAML, OpenCV FileStorage YAML/XML) "
       "into a monocle calibration file."},
      {"", "intrinsics export", "A monocle calibration's intrinsics as ROS camera_info YAML."},
      {"", "floor calibrate",
       "Camera height, pitch, yaw and roll from one image of a chessboard on the floor "
       "(or the running service's camera: --camera ID)."},
      {"", "floor measure",
       "Robot-frame 3D points (metres) from floor pixels \"u,v\" or from pixels standing "
       "vertically above a floor pixel \"u,v@fu,fv\" (or asked of the service: --camera ID)."},
      {"", "floor project",
       "The pixel where the calibrated camera sees each robot-frame point (metres)."},
      {"", "floor map",
       "The floor from above: the camera's footprint and a floor point's 1-sigma as colour."},
      {"", "corner locate",
       "Camera position and pan, tilt, swing from the ceiling corner in each image; the "
       "robot's pose in a room map (--map); the service's poses (--camera ID)."},
      {"", "corner fit-mount",
       "The tilt and roll of the camera's mount from images taken with the robot on the floor."},
      {"", "map check", "Validates a room map and lists its rooms and ceiling corners."},
      {"", "map draw", "The map from above with a true path and the poses located in it."},
      {"Live, from the running service (monocled) over DDS:", "view",
       "The camera's live frame with what the service measured in it drawn on it."},
      {"", "status", "The service's cameras: state, fps, dropped frames, latency, last error."},
      {"", "record",
       "Records the service's poses, calibrations, status, requests, replies and frames (MCAP)."},
      {"Recordings, cameras and simulation:", "info",
       "What a recording holds: time span, cameras, messages per topic."},
      {"", "replay",
       "A recording's frames through monocled's corner pipeline again: one pose per frame."},
      {"", "cameras", "Lists the GigE Vision and USB3 Vision cameras Aravis sees."},
      {"", "snapshot", "Grabs one frame from a camera given by id, IP address or serial."},
      {"", "simcam", "Serves a simulated GigE Vision camera whose frames are rendered scenes."},
      {"", "render corner", "Renders a room corner as the camera at that pose sees it."},
      {"", "render room",
       "Renders what the robot's camera sees in a room of the map, at a pose or along a path."},
      {"", "render floor",
       "Renders a chessboard (and boxes) on the floor as the calibrated camera sees it."},
      {"", "render boards",
       "Board views rendered with known intrinsics, to try or check `intrinsics calibrate`."},
      {"Security:", "security init",
       "A DDS Security keystore: a CA, identities for monocled and each client, permissions."},
  };
  return commands;
}

std::vector<std::string> CommandNames() {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const CommandEntry& command : Commands())
    if (seen.insert(command.name).second) names.push_back(command.name);
  return names;
}

std::string TopLevelUsage() {
  std::ostringstream out;
  out << "monocle — measurements from one camera on a mobile robot\n\n"
         "Usage: monocle COMMAND [ARGS...]    (monocle COMMAND --help for its options)\n";
  for (const CommandEntry& command : Commands()) {
    if (*command.heading != '\0') out << "\n" << command.heading << "\n";
    const std::string name = command.name;
    out << "  " << name << std::string(std::max<size_t>(22 - name.size(), 2), ' ')
        << WrapText(command.summary, 24, 24, 96) << "\n";
  }
  out << "\nLive forms take --domain D, --timeout S and --security DIR (`monocle security init`).\n"
         "monocle --version prints the version.\n"
         "monocle help --markdown prints the reference of every command (client/cli/README.md).\n"
         "Exit status: 0 success, 1 a measurement or input failed, 2 wrong command line.\n";
  return out.str();
}

int RunCommand(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << TopLevelUsage();
    return args.empty() ? kExitUsage : kExitOk;
  }
  const std::string command = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (command == "help") return HelpCommand(rest);
  if (command == "floor") return FloorCommand(rest);
  if (command == "corner") return CornerCommand(rest);
  if (command == "cameras" || command == "snapshot" || command == "simcam")
    return CameraCommand(command, rest);
  if (command == "intrinsics") return IntrinsicsCommand(rest);
  if (command == "render") return RenderCommand(rest);
  if (command == "status") return StatusCommand(rest);
  if (command == "security") return SecurityCommand(rest);
  if (command == "map") return MapCommand(rest);
  if (command == "record") return RecordCommand(rest);
  if (command == "info") return InfoCommand(rest);
  if (command == "replay") return ReplayCommand(rest);
  if (command == "view") return ViewCommand(rest);
  if (command == "--version") {
    std::cout << "monocle " MONOCLE_VERSION "\n";
    return kExitOk;
  }
  std::cerr << "monocle: error: unknown command '" << command << "'\n\n" << TopLevelUsage();
  return kExitUsage;
}

namespace {

// What `monocle NAME --help` prints, captured.
std::string HelpOf(const std::string& name) {
  std::vector<std::string> args;
  std::istringstream words(name);
  for (std::string word; words >> word;) args.push_back(word);
  args.push_back("--help");
  std::ostringstream captured;
  std::streambuf* const previous = std::cout.rdbuf(captured.rdbuf());
  RunCommand(args);
  std::cout.rdbuf(previous);
  return captured.str();
}

std::string Anchor(const std::string& name) {
  std::string anchor = "monocle-";
  for (char c : name) anchor += c == ' ' ? '-' : c;
  return anchor;
}

void PrintReference(std::ostream& out) {
  out << "# `monocle` command reference\n\n"
         "Generated by `monocle help --markdown` from the commands' own `--help`, which each\n"
         "command makes from its declared options (command_line.h); do not edit by hand\n"
         "(`command_reference_test` fails when this page and the program differ). How to use\n"
         "the commands, task by task: [GUIDE.md](GUIDE.md).\n\n"
         "| command | what |\n|---|---|\n";
  for (const CommandEntry& command : Commands()) {
    std::string summary = command.summary;
    for (char& c : summary)
      if (c == '\n') c = ' ';
    out << "| [`" << command.name << "`](#" << Anchor(command.name) << ") | " << summary << " |\n";
  }
  out << "\n## Usage\n\n```\n" << TopLevelUsage() << "```\n";
  for (const std::string& name : CommandNames())
    out << "\n## monocle " << name << "\n\n```\n" << HelpOf(name) << "```\n";
}

}  // namespace

int HelpCommand(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << TopLevelUsage();
    return kExitOk;
  }
  if (args.size() == 1 && args[0] == "--list") {
    for (const std::string& name : CommandNames()) std::cout << name << "\n";
    return kExitOk;
  }
  if (args.size() == 1 && args[0] == "--markdown") {
    PrintReference(std::cout);
    return kExitOk;
  }
  return Fail("help takes --list or --markdown (or nothing: the usage)", kExitUsage);
}

}  // namespace monocle::cli
