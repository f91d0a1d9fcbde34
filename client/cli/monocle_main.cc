// The monocle command line. Offline forms work on images and calibration files; the
// --camera forms and `status` ask the running service over DDS (monocle::Client).
#include <malloc.h>

#include <iostream>
#include <string>
#include <vector>

#include "client/cli/commands.h"

namespace {

constexpr const char* kUsage = R"(monocle — measurements from one camera on a mobile robot

Usage: monocle COMMAND [ARGS...]    (monocle COMMAND --help for details)

Commands:
  floor calibrate IMAGE --calibration CAL.pbtxt --board COLSxROWS --square METRES
                  [--method full|paper] [--write] [--json]
      Camera height, pitch, yaw and roll from one image of a chessboard on the floor.
  floor measure --calibration CAL.pbtxt [--pixel-sigma PX] [--json] POINT...
      Robot-frame 3D points (metres) from floor pixels "u,v" or from pixels standing
      vertically above a floor pixel "u,v@fu,fv".
  floor project --calibration CAL.pbtxt [--json] X,Y,Z...
      The pixel where the calibrated camera sees each robot-frame point (metres).
  floor map --calibration CAL.pbtxt --out MAP.png [--range M] [--pixel-sigma PX]
      The floor from above: the camera's footprint and a floor point's 1-sigma as colour.
  corner locate IMAGE... --calibration CAL.pbtxt [--ceiling-distance Z] [--json] [--overlay DIR]
      Camera position and pan, tilt, swing from the ceiling corner in each image.
  corner locate IMAGE... --calibration CAL.pbtxt --map MAP.pbtxt --mount MOUNT.pbtxt
                [--prior X,Y,HEADING_DEG] [--track] [--json]
      The robot's pose in a room map from whichever corner is in view, and which corner.
  corner fit-mount IMAGE... --calibration CAL.pbtxt --mount MOUNT.pbtxt [--out NEW.pbtxt]
      The tilt and roll of the camera's mount from images taken with the robot on the floor.
  map check MAP.pbtxt [--mount MOUNT.pbtxt]
      Validates a room map and lists its rooms and ceiling corners.
  map draw MAP.pbtxt --out MAP.png [--trajectory FILE] [--poses POSES.jsonl]
      The map from above with a true path and the poses located in it.
  intrinsics calibrate IMAGE... --board COLSxROWS --square METRES --out CAL.pbtxt
      Focal lengths, principal point and lens distortion from several board images.
  render corner --calibration CAL.pbtxt --pose X,Y,Z,PAN,TILT,SWING --out IMG.png
                [--noise SIGMA] [--seed N] [--clutter] [--lighting] [--realistic [--raw]]
      Renders a room corner as the camera at that pose sees it.
  render room --map MAP.pbtxt --mount MOUNT.pbtxt --calibration CAL.pbtxt
              (--pose X,Y,HEADING_DEG --out IMG.png | --trajectory FILE --out DIR)
              [--realistic [--raw]]
      Renders what the robot's camera sees in a room of the map, at a pose or along a path.
  render floor --calibration CAL.pbtxt --board COLSxROWS --square METRES --out IMG.png
               [--noise SIGMA] [--seed N] [--board-origin X,Y] [--box X,Y,W,D,H]...
      Renders a chessboard (and boxes) on the floor as the calibrated camera sees it.

Live, from the running service (monocled) over DDS [--domain D] [--timeout S] [--security DIR]:
  corner locate --camera ID [--count N] [--follow] [--json]
      The camera's poses as the service streams them.
  floor measure --camera ID [--pixel-sigma PX] [--json] POINT...
      Points measured by the service with its current calibration of that camera.
  floor calibrate --camera ID --board COLSxROWS --square METRES [--json]
      The service calibrates the floor from the camera's next frame, stores and publishes it.
  view --camera ID --out LIVE.png [--every S]
      The camera's live frame with what the service measured in it drawn on it.
  status [--watch] [--json]
      The service's cameras: state, fps, dropped frames, latency, last error.

  record --out FILE.mcap [--camera ID]... [--frames none|every|N] [--duration S] [--zstd]
      Records the service's poses, calibrations, status, requests, replies and frames (MCAP).

  security init DIR [--client NAME[:reader|operator]]...
      A DDS Security keystore: a CA, identities for monocled and each client, permissions.

  cameras [--json]
      Lists the GigE Vision and USB3 Vision cameras Aravis sees.
  snapshot CAMERA --out IMG.png
      Grabs one frame from a camera given by id, IP address or serial.
  info FILE.mcap [--json]
      What a recording holds: time span, cameras, messages per topic.
  replay FILE.mcap [--camera ID] [--rate X] [--json]
      A recording's frames through monocled's corner pipeline again: one pose per frame.
  simcam --scene corner|floor [--ip 127.0.0.1] [--width W --height H --fps F] [--truth FILE]
      Serves a simulated GigE Vision camera whose frames are rendered scenes.

Exit status: 0 success, 1 a measurement or input failed, 2 wrong command line.
)";

}  // namespace

int main(int argc, char** argv) {
  // Per-image buffers of a megabyte or more would otherwise be mmap'ed and unmapped for
  // every image, paying page faults each time (a fifth of `corner locate`'s time over many
  // files); keep them in the heap for reuse instead.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? monocle::cli::kExitUsage : monocle::cli::kExitOk;
  }
  const std::string command = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (command == "floor") return monocle::cli::FloorCommand(rest);
  if (command == "corner") return monocle::cli::CornerCommand(rest);
  if (command == "cameras" || command == "snapshot" || command == "simcam") {
    return monocle::cli::CameraCommand(command, rest);
  }
  if (command == "intrinsics") return monocle::cli::IntrinsicsCommand(rest);
  if (command == "render") return monocle::cli::RenderCommand(rest);
  if (command == "status") return monocle::cli::StatusCommand(rest);
  if (command == "security") return monocle::cli::SecurityCommand(rest);
  if (command == "map") return monocle::cli::MapCommand(rest);
  if (command == "record") return monocle::cli::RecordCommand(rest);
  if (command == "info") return monocle::cli::InfoCommand(rest);
  if (command == "replay") return monocle::cli::ReplayCommand(rest);
  if (command == "view") return monocle::cli::ViewCommand(rest);
  if (command == "--version") {
    std::cout << "monocle 0.1.0\n";
    return 0;
  }
  std::cerr << "monocle: error: unknown command '" << command << "'\n\n" << kUsage;
  return monocle::cli::kExitUsage;
}
