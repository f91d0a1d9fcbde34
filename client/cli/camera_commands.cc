// monocle cameras | snapshot | simcam: cameras through Aravis.
#include <cmath>
#include <csignal>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "camera/aravis/aravis_source.h"
#include "camera/sim/sim_gv_camera.h"
#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "service/io/base_trajectory_file.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {
namespace {

constexpr const char* kCamerasHelp = R"(Usage: monocle cameras [--json]

Lists the cameras Aravis sees (GigE Vision and USB3 Vision): id, vendor, model, serial,
address, interface. A simulated camera on 127.0.0.1 may not be discovered: open it by its
address (monocle snapshot 127.0.0.1 ...).
)";

constexpr const char* kSnapshotHelp =
    R"(Usage: monocle snapshot CAMERA --out IMG.png [--pixel-format F] [--timeout MS]

Grabs one frame from CAMERA (an Aravis device id, an IPv4 address or a serial number)
and writes it as 8-bit grey (Mono16, Bayer and RGB frames are converted).

  --pixel-format F  GenICam pixel format to request (default Mono8)
  --timeout MS      how long to wait for a frame, milliseconds (default 3000)
  --exposure US     exposure time, microseconds
  --gain DB         gain, dB
  --fps HZ          frame rate, Hz
  --region X,Y,W,H  region of interest, pixels
  --packet-size B   GigE Vision packet size, bytes; --packet-delay T inter-packet delay, ticks
  --feature N=V     any other GenICam feature by name (repeatable)
Every value is checked against the camera's range first; the error names the feature.
The ids sim-corner, sim-corner-realistic (a white-painted room) and sim-floor are built-in
simulated cameras.
)";

constexpr const char* kSimcamHelp =
    R"(Usage: monocle simcam --scene corner|floor [--ip 127.0.0.1] [--serial S] [--width W --height H]
                      [--fps F] [--frames N] [--trajectory FILE] [--truth FILE]
                      [--calibration-out CAL.pbtxt] [--realistic [--look-seed N] [--raw]]
       monocle simcam --scene room --map MAP.pbtxt --mount MOUNT.pbtxt --trajectory FILE
                      [--ip ...] [--fps F] [--truth FILE] [--calibration-out CAL.pbtxt]
                      [--realistic [--look-seed N] [--raw]]

Serves a simulated GigE Vision camera (Aravis's ArvGvFakeCamera) on a local address whose
frames are rendered scenes: `corner` a ceiling corner seen from a robot moving along a
trajectory of N poses (frame id k shows pose k mod N), `floor` a chessboard and a box on
the floor, `room` a robot driving through a room of a map (service/README.md, "Room map"): frame id k
shows trajectory pose k mod N, seen by a wide lens (f 700 px at 1280 px wide) on the mount.
Runs until Ctrl-C (SIGINT) or SIGTERM.

  --ip A              address to serve on (default 127.0.0.1; one camera per address)
  --serial S          serial number, 1 to 15 characters (default MONOCLE-SIM)
  --width/--height    image size, pixels (default 1280x1024)
  --fps F             frame rate, Hz (default 30)
  --frames N          poses on the built-in trajectory (default 16)
  --trajectory FILE   corner: poses to drive through instead, one a line:
                      x,y,z,pan,tilt,swing (metres, radians, corner frame); room: the
                      robot base's poses, x_m y_m heading_deg a line (map frame)
  --map, --mount      room: the room map and the camera's mount on the robot
  --truth FILE        write the ground truth: one JSON object per pose, keyed by
                      frame id modulo N (corner: x y z pan tilt swing; floor: height
                      pitch yaw roll; room: the base's x y (m) and heading_deg in the map)
  --calibration-out   write the camera's calibration file (intrinsics, and the ceiling
                      distance or the floor pose) for `monocle corner locate` and friends
  --realistic         corner: a white-painted room as cameras photograph it (surfaces
                      8-40 grey levels apart, shading, hot-spot, vignetting, blur, noise,
                      JPEG; see `monocle render corner --help`), one look drawn from
                      --look-seed N (default 1), new noise in every frame
  --raw               with --realistic: no JPEG step, as a machine-vision camera delivers
                      its frames
)";

int Cameras(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kCamerasHelp;
    return kExitOk;
  }
  auto args = Args::Parse(argv, {{}, {"--json"}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto cams = ListCameras();
  if (args->Has("--json")) {
    std::cout << "[";
    for (size_t i = 0; i < cams.size(); ++i) {
      const auto& c = cams[i];
      std::cout << (i ? "," : "") << "{\"id\":\"" << c.id << "\",\"vendor\":\"" << c.vendor
                << "\",\"model\":\"" << c.model << "\",\"serial\":\"" << c.serial
                << "\",\"address\":\"" << c.address << "\",\"interface\":\"" << c.protocol << "\"}";
    }
    std::cout << "]\n";
  } else if (cams.empty()) {
    std::cout << "no cameras found\n";
  } else {
    for (const auto& c : cams) {
      std::cout << c.id << "  " << c.vendor << " " << c.model << "  serial " << c.serial << "  "
                << c.address << "  " << c.protocol << "\n";
    }
  }
  return kExitOk;
}

int Snapshot(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kSnapshotHelp;
    return kExitOk;
  }
  auto args =
      Args::Parse(argv, {{"--out", "--pixel-format", "--timeout", "--exposure", "--gain", "--fps",
                          "--region", "--packet-size", "--packet-delay", "--feature"},
                         {}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (args->positionals().size() != 1)
    return Fail("snapshot takes one CAMERA (see --help)", kExitUsage);
  const auto out = args->Require("--out");
  if (!out) return Fail(out.error(), kExitUsage);
  const auto timeout = args->GetDouble("--timeout", 3000);
  if (!timeout || *timeout <= 0)
    return Fail("--timeout must be a positive number of milliseconds", kExitUsage);
  AravisOptions options;
  options.device = args->positionals()[0];
  options.pixel_format = args->Get("--pixel-format").value_or("Mono8");
  for (const auto& [flag, field] :
       {std::pair{"--exposure", &options.exposure_us}, std::pair{"--gain", &options.gain},
        std::pair{"--fps", &options.frame_rate_hz}}) {
    if (!args->Get(flag)) continue;
    const auto v = args->GetDouble(flag, 0);
    if (!v) return Fail(v.error(), kExitUsage);
    *field = *v;
  }
  for (const auto& [flag, field] :
       {std::pair{"--packet-size", &options.packet_size_bytes},
        std::pair{"--packet-delay", &options.inter_packet_delay_ticks}}) {
    if (!args->Get(flag)) continue;
    const auto v = args->GetDouble(flag, 0);
    if (!v || *v < 0) return Fail(std::string(flag) + " must be a whole number >= 0", kExitUsage);
    *field = static_cast<int>(*v);
  }
  if (const auto region = args->Get("--region")) {
    const auto v = ParseNumberList(*region);
    if (!v || v->size() != 4)
      return Fail("--region '" + *region + "' is not X,Y,W,H in pixels", kExitUsage);
    options.region = std::array<int, 4>{static_cast<int>((*v)[0]), static_cast<int>((*v)[1]),
                                        static_cast<int>((*v)[2]), static_cast<int>((*v)[3])};
  }
  for (const auto& f : args->GetAll("--feature")) {
    const auto eq = f.find('=');
    if (eq == std::string::npos || eq == 0)
      return Fail("--feature '" + f + "' is not NAME=VALUE", kExitUsage);
    options.features.emplace_back(f.substr(0, eq), f.substr(eq + 1));
  }
  auto source = AravisSource::Open(options);
  if (!source) return Fail(source.error(), kExitFailure);
  const auto frame = (*source)->Next(std::chrono::milliseconds(static_cast<int64_t>(*timeout)));
  if (!frame) return Fail(frame.error(), kExitFailure);
  if (auto written = WriteImage(*out, frame->grey); !written)
    return Fail(written.error(), kExitFailure);
  std::cout << "frame " << frame->sequence << " " << frame->grey.cols << "x" << frame->grey.rows
            << " from " << (*source)->info().vendor << " " << (*source)->info().model
            << " written to " << *out << "\n";
  return kExitOk;
}

// The simulated camera's truth per frame, one JSON object a line (--truth FILE).
Status WriteTruth(const SimCameraOptions& o, const SimGvCamera& cam, const std::string& path) {
  std::ostringstream os;
  os << std::setprecision(12);
  if (o.scene == SimScene::kRoom) {
    const auto& t = o.base_trajectory;
    for (size_t i = 0; i < t.size(); ++i) {
      os << "{\"frame_id_mod\":" << i << ",\"period\":" << t.size() << ",\"x\":" << t[i].x_m
         << ",\"y\":" << t[i].y_m << ",\"heading_deg\":" << t[i].heading_rad * 180 / M_PI << "}\n";
    }
  } else if (o.scene == SimScene::kCorner) {
    const auto& t = cam.trajectory();
    for (size_t i = 0; i < t.size(); ++i) {
      os << "{\"frame_id_mod\":" << i << ",\"period\":" << t.size() << ",\"x\":" << t[i].x_m
         << ",\"y\":" << t[i].y_m << ",\"z\":" << t[i].z_m << ",\"pan\":" << t[i].pan_rad
         << ",\"tilt\":" << t[i].tilt_rad << ",\"swing\":" << t[i].swing_rad << "}\n";
    }
  } else {
    const auto& f = cam.floor_pose();
    os << "{\"frame_id_mod\":0,\"period\":1,\"height\":" << f.height_m
       << ",\"pitch\":" << f.pitch_rad << ",\"yaw\":" << f.yaw_rad << ",\"roll\":" << f.roll_rad
       << "}\n";
  }
  return WriteFileAtomically(path, os.str());
}

// A calibration file of the simulated camera: its intrinsics and the scene's ceiling
// distance or floor pose (--calibration-out FILE).
Status WriteSimCalibration(const SimCameraOptions& o, const SimGvCamera& cam,
                           const std::string& path) {
  CameraCalibration cal;
  cal.intrinsics = cam.intrinsics();
  if (o.scene == SimScene::kCorner) {
    cal.ceiling_distance_m = cam.trajectory().front().z_m;
  } else if (o.scene == SimScene::kFloor) {
    cal.floor = FloorCalibration{};
    cal.floor->pose = cam.floor_pose();
  }
  return SaveCalibrationFileAtomically(path, cal);
}

int Simcam(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kSimcamHelp;
    return kExitOk;
  }
  auto args = Args::Parse(
      argv, {{"--scene", "--ip", "--serial", "--width", "--height", "--fps", "--frames", "--truth",
              "--calibration-out", "--trajectory", "--look-seed", "--map", "--mount"},
             {"--realistic", "--raw"}});
  if (!args) return Fail(args.error(), kExitUsage);
  SimCameraOptions o;
  const std::string scene = args->Get("--scene").value_or("");
  if (scene != "corner" && scene != "floor" && scene != "room")
    return Fail("--scene must be corner, floor or room", kExitUsage);
  o.scene = scene == "corner" ? SimScene::kCorner
            : scene == "room" ? SimScene::kRoom
                              : SimScene::kFloor;
  o.ip = args->Get("--ip").value_or(o.ip);
  o.serial = args->Get("--serial").value_or(o.serial);
  const auto w = args->GetDouble("--width", o.width), h = args->GetDouble("--height", o.height);
  const auto fps = args->GetDouble("--fps", o.fps),
             frames = args->GetDouble("--frames", o.trajectory_frames);
  if (!w || !h || !fps || !frames || *frames < 1)
    return Fail("--width, --height, --fps, --frames must be positive numbers", kExitUsage);
  o.width = static_cast<int>(*w);
  o.height = static_cast<int>(*h);
  o.fps = *fps;
  o.trajectory_frames = static_cast<int>(*frames);
  o.realistic = args->Has("--realistic");
  o.raw = args->Has("--raw");
  if (o.raw && !o.realistic)
    return Fail("--raw goes with --realistic (the clean look is not compressed)", kExitUsage);
  const auto look_seed = args->GetDouble("--look-seed", 1);
  if (!look_seed || *look_seed < 0 || *look_seed != std::floor(*look_seed))
    return Fail("--look-seed must be a whole number >= 0", kExitUsage);
  o.look_seed = static_cast<uint64_t>(*look_seed);
  if (o.scene == SimScene::kRoom) {
    for (const char* required : {"--map", "--mount", "--trajectory"}) {
      if (!args->Get(required))
        return Fail(std::string("--scene room needs ") + required + " (see --help)", kExitUsage);
    }
    auto map = LoadRoomMapFile(*args->Get("--map"));
    if (!map) return Fail(map.error(), kExitFailure);
    auto mount = LoadCameraMountFile(*args->Get("--mount"), *map);
    if (!mount) return Fail(mount.error(), kExitFailure);
    auto poses = LoadBaseTrajectoryFile(*args->Get("--trajectory"));
    if (!poses) return Fail(poses.error(), kExitFailure);
    o.room_map = std::move(*map);
    o.mount = *mount;
    o.base_trajectory = std::move(*poses);
  } else if (const auto file = args->Get("--trajectory")) {
    auto poses = ReadTrajectoryFile(*file);
    if (!poses) return Fail(poses.error(), kExitUsage);
    o.trajectory = *poses;
  }

  // Block the stop signals before any thread starts, then wait for them here.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);

  const size_t poses = o.scene == SimScene::kRoom ? o.base_trajectory.size()
                       : o.trajectory.empty()     ? static_cast<size_t>(o.trajectory_frames)
                                                  : o.trajectory.size();
  std::cerr << "rendering " << (o.scene == SimScene::kFloor ? 2 : poses) << " frames...\n";
  auto cam = SimGvCamera::Start(o);
  if (!cam) return Fail(cam.error(), kExitFailure);
  if (const auto look = SimRealisticLook(o, (*cam)->intrinsics())) std::cerr << *look << "\n";
  if (const auto truth = args->Get("--truth")) {
    if (auto w = WriteTruth(o, **cam, *truth); !w) return Fail(w.error(), kExitFailure);
  }
  if (const auto cal_out = args->Get("--calibration-out")) {
    if (auto w = WriteSimCalibration(o, **cam, *cal_out); !w) return Fail(w.error(), kExitFailure);
  }
  std::cerr << "serving simulated GigE Vision camera '" << o.serial << "' on " << o.ip << " ("
            << o.width << "x" << o.height << " Mono8, " << o.fps << " fps, scene " << scene
            << "); Ctrl-C stops\n";
  int signal = 0;
  sigwait(&stop, &signal);
  std::cerr << "stopping\n";
  return kExitOk;
}

}  // namespace

int CameraCommand(const std::string& command, const std::vector<std::string>& args) {
  if (command == "cameras") return Cameras(args);
  if (command == "snapshot") return Snapshot(args);
  return Simcam(args);
}

}  // namespace monocle::cli
