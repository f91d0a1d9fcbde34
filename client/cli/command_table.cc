#include "client/cli/command_table.h"

#include <iostream>
#include <set>
#include <sstream>

#include "client/cli/commands.h"

namespace monocle::cli {

const std::vector<CommandForm>& CommandForms() {
  static const std::vector<CommandForm> forms = {
      {0, "", "floor calibrate",
       "floor calibrate IMAGE --calibration CAL.pbtxt --board COLSxROWS --square METRES\n"
       "                [--method full|paper] [--write] [--json]",
       "Camera height, pitch, yaw and roll from one image of a chessboard on the floor."},
      {0, "", "floor measure",
       "floor measure --calibration CAL.pbtxt [--pixel-sigma PX] [--json] POINT...",
       "Robot-frame 3D points (metres) from floor pixels \"u,v\" or from pixels standing\n"
       "vertically above a floor pixel \"u,v@fu,fv\"."},
      {0, "", "floor project", "floor project --calibration CAL.pbtxt [--json] X,Y,Z...",
       "The pixel where the calibrated camera sees each robot-frame point (metres)."},
      {0, "", "floor map",
       "floor map --calibration CAL.pbtxt --out MAP.png [--range M] [--pixel-sigma PX]",
       "The floor from above: the camera's footprint and a floor point's 1-sigma as colour."},
      {0, "", "corner locate",
       "corner locate IMAGE... --calibration CAL.pbtxt [--ceiling-distance Z] [--json] [--overlay "
       "DIR]",
       "Camera position and pan, tilt, swing from the ceiling corner in each image."},
      {0, "", "corner locate",
       "corner locate IMAGE... --calibration CAL.pbtxt --map MAP.pbtxt --mount MOUNT.pbtxt\n"
       "              [--prior X,Y,HEADING_DEG] [--track] [--json]",
       "The robot's pose in a room map from whichever corner is in view, and which corner."},
      {0, "", "corner fit-mount",
       "corner fit-mount IMAGE... --calibration CAL.pbtxt --mount MOUNT.pbtxt [--out NEW.pbtxt]",
       "The tilt and roll of the camera's mount from images taken with the robot on the floor."},
      {0, "", "map check", "map check MAP.pbtxt [--mount MOUNT.pbtxt]",
       "Validates a room map and lists its rooms and ceiling corners."},
      {0, "", "map draw",
       "map draw MAP.pbtxt --out MAP.png [--trajectory FILE] [--poses POSES.jsonl]",
       "The map from above with a true path and the poses located in it."},
      {0, "", "intrinsics calibrate",
       "intrinsics calibrate IMAGE... --board COLSxROWS --square METRES --out CAL.pbtxt",
       "Focal lengths, principal point and lens distortion from several board images."},
      {0, "", "render corner",
       "render corner --calibration CAL.pbtxt --pose X,Y,Z,PAN,TILT,SWING --out IMG.png\n"
       "              [--noise SIGMA] [--seed N] [--clutter] [--lighting] [--realistic [--raw]]",
       "Renders a room corner as the camera at that pose sees it."},
      {0, "", "render room",
       "render room --map MAP.pbtxt --mount MOUNT.pbtxt --calibration CAL.pbtxt\n"
       "            (--pose X,Y,HEADING_DEG --out IMG.png | --trajectory FILE --out DIR)\n"
       "            [--realistic [--raw]]",
       "Renders what the robot's camera sees in a room of the map, at a pose or along a path."},
      {0, "", "render floor",
       "render floor --calibration CAL.pbtxt --board COLSxROWS --square METRES --out IMG.png\n"
       "             [--noise SIGMA] [--seed N] [--board-origin X,Y] [--box X,Y,W,D,H]...",
       "Renders a chessboard (and boxes) on the floor as the calibrated camera sees it."},
      {0, "", "render boards",
       "render boards --calibration CAL.pbtxt --board COLSxROWS --square METRES --views N\n"
       "              --out-dir DIR [--seed N] [--spread good|fronto|corner]",
       "Board views rendered with known intrinsics, to try or check `intrinsics calibrate`."},
      {1,
       "Live, from the running service (monocled) over DDS [--domain D] [--timeout S] [--security "
       "DIR]:",
       "corner locate", "corner locate --camera ID [--count N] [--follow] [--json]",
       "The camera's poses as the service streams them."},
      {1, "", "floor measure", "floor measure --camera ID [--pixel-sigma PX] [--json] POINT...",
       "Points measured by the service with its current calibration of that camera."},
      {1, "", "floor calibrate",
       "floor calibrate --camera ID --board COLSxROWS --square METRES [--json]",
       "The service calibrates the floor from the camera's next frame, stores and publishes it."},
      {1, "", "view", "view --camera ID --out LIVE.png [--every S]",
       "The camera's live frame with what the service measured in it drawn on it."},
      {1, "", "status", "status [--watch] [--json]",
       "The service's cameras: state, fps, dropped frames, latency, last error."},
      {2, "", "record",
       "record --out FILE.mcap [--camera ID]... [--frames none|every|N] [--duration S] [--zstd]",
       "Records the service's poses, calibrations, status, requests, replies and frames (MCAP)."},
      {3, "", "security init", "security init DIR [--client NAME[:reader|operator]]...",
       "A DDS Security keystore: a CA, identities for monocled and each client, permissions."},
      {4, "", "cameras", "cameras [--json]",
       "Lists the GigE Vision and USB3 Vision cameras Aravis sees."},
      {4, "", "snapshot", "snapshot CAMERA --out IMG.png",
       "Grabs one frame from a camera given by id, IP address or serial."},
      {4, "", "info", "info FILE.mcap [--json]",
       "What a recording holds: time span, cameras, messages per topic."},
      {4, "", "replay", "replay FILE.mcap [--camera ID] [--rate X] [--json]",
       "A recording's frames through monocled's corner pipeline again: one pose per frame."},
      {4, "", "simcam",
       "simcam --scene corner|floor [--ip 127.0.0.1] [--width W --height H --fps F] [--truth FILE]",
       "Serves a simulated GigE Vision camera whose frames are rendered scenes."},
  };
  return forms;
}

std::vector<std::string> CommandNames() {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const CommandForm& form : CommandForms())
    if (seen.insert(form.name).second) names.push_back(form.name);
  return names;
}

namespace {

// Each line of `text` with `indent` before it.
void Indented(std::ostream& out, const std::string& text, const std::string& indent) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) out << indent << line << "\n";
}

}  // namespace

std::string TopLevelUsage() {
  std::ostringstream out;
  out << "monocle — measurements from one camera on a mobile robot\n\n"
         "Usage: monocle COMMAND [ARGS...]    (monocle COMMAND --help for details)\n\n"
         "Commands:\n";
  int group = CommandForms().front().group;
  for (const CommandForm& form : CommandForms()) {
    if (form.group != group) out << "\n";
    group = form.group;
    if (*form.heading != '\0') out << form.heading << "\n";
    Indented(out, form.synopsis, "  ");
    Indented(out, form.summary, "      ");
  }
  out << "\nmonocle help --markdown prints the reference of every command (client/cli/README.md).\n"
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
    std::cout << "monocle 0.1.0\n";
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
         "Generated by `monocle help --markdown` from the commands' own `--help`; do not edit by\n"
         "hand (`command_reference_test` fails when this page and the program differ). How to\n"
         "use the commands, task by task: [GUIDE.md](GUIDE.md).\n\n"
         "| command | what |\n|---|---|\n";
  std::set<std::string> listed;
  for (const CommandForm& form : CommandForms()) {
    if (!listed.insert(form.name).second) continue;
    std::string summary = form.summary;
    for (char& c : summary)
      if (c == '\n') c = ' ';
    out << "| [`" << form.name << "`](#" << Anchor(form.name) << ") | " << summary << " |\n";
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
