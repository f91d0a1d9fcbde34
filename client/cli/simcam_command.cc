// monocle simcam: a simulated GigE Vision camera serving rendered scenes through Aravis.
#include <cmath>
#include <csignal>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "camera/sim/sim_gv_camera.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "service/io/base_trajectory_file.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {
namespace {

constexpr const char* kAbout =
    R"(Serves a simulated GigE Vision camera (Aravis's ArvGvFakeCamera) on a local address whose
frames are rendered scenes: `corner` a ceiling corner seen from a robot driving a closed loop
under it, N frames a lap (frame id k shows pose k mod N), `floor` a chessboard and a box on
the floor, `room` a robot driving through a room of a map (service/README.md, "Room map"): frame id k
shows trajectory pose k mod N, seen by a wide lens (f 700 px at 1280 px wide) on the mount.
Runs until Ctrl-C (SIGINT) or SIGTERM.)";

struct SimcamArgs {
  SimCameraOptions options;
  std::string scene;
  std::optional<std::string> trajectory_path, map_path, mount_path, truth_path, calibration_out;
  int look_seed = 1;
};

void DeclareSimcam(CommandLine& line, SimcamArgs* a) {
  SimCameraOptions& o = a->options;
  line.Choice("--scene", &a->scene, {"corner", "floor", "room"},
              "what the camera sees: a ceiling corner, a chessboard on the floor, or a room of "
              "a map");
  line.Require("--scene");
  line.Text("--ip", &o.ip, "A", "address to serve on (default 127.0.0.1; one camera per address)");
  line.Text("--serial", &o.serial, "S", "serial number, 1 to 15 characters (default MONOCLE-SIM)");
  line.Whole("--width", &o.width, "W", "image width", In("pixels").AtLeast(1));
  line.Whole("--height", &o.height, "H", "image height", In("pixels").AtLeast(1));
  line.Number("--fps", &o.fps, "F", "frame rate", In("Hz").Above(0));
  line.Whole("--frames", &o.trajectory_frames, "N",
             "corner: frames in one lap of the built-in drive (a closed loop, so frame id k "
             "shows pose k mod N and the motion runs on past the lap)",
             In("frames").AtLeast(1));
  line.Number("--speed", &o.speed_mps, "V", "corner: the robot's speed on the built-in drive",
              In("m/s").AtLeast(0));
  line.Number("--turn", &o.turn_deg_per_s, "W",
              "corner: the peak rate of the robot's own turning on the built-in drive, on top "
              "of keeping the corner in view",
              In("deg/s").AtLeast(0));
  line.Text("--trajectory", &a->trajectory_path, "FILE",
            "corner: poses to drive through instead, one a line: x,y,z,pan,tilt,swing (metres, "
            "radians, corner frame); room: the robot base's poses, x_m y_m heading_deg a line "
            "(map frame)");
  line.Text("--map", &a->map_path, "MAP.pbtxt", "room: the room map");
  line.Text("--mount", &a->mount_path, "MOUNT.pbtxt", "room: the camera's mount on the robot");
  line.Text("--truth", &a->truth_path, "FILE",
            "write the ground truth: one JSON object per pose, keyed by frame id modulo N "
            "(corner: x y z pan tilt swing; floor: height pitch yaw roll; room: the base's x y "
            "(m) and heading_deg in the map)");
  line.Text("--calibration-out", &a->calibration_out, "CAL.pbtxt",
            "write the camera's calibration file (intrinsics, and the ceiling distance or the "
            "floor pose) for `monocle corner locate` and friends");
  line.Flag("--realistic", &o.realistic,
            "corner: a white-painted room as cameras photograph it (surfaces 8-40 grey levels "
            "apart, shading, hot-spot, vignetting, blur, noise, JPEG; see `monocle render corner "
            "--help`), one look drawn from --look-seed, new noise in every frame");
  line.Whole("--look-seed", &a->look_seed, "N", "the realistic look's seed", In("").AtLeast(0));
  line.Flag("--raw", &o.raw,
            "with --realistic: no JPEG step, as a machine-vision camera delivers its frames");
}

// The scene's poses from the files named; the exit status of a failure, or kExitOk.
int LoadScene(const SimcamArgs& a, SimCameraOptions* o) {
  if (o->scene == SimScene::kRoom) {
    for (const auto& [flag, given] :
         {std::pair{"--map", &a.map_path}, std::pair{"--mount", &a.mount_path},
          std::pair{"--trajectory", &a.trajectory_path}}) {
      if (!*given)
        return Fail(std::string("--scene room needs ") + flag + " (see --help)", kExitUsage);
    }
    auto map = LoadRoomMapFile(*a.map_path);
    if (!map) return Fail(map.error(), kExitFailure);
    auto mount = LoadCameraMountFile(*a.mount_path, *map);
    if (!mount) return Fail(mount.error(), kExitFailure);
    auto poses = LoadBaseTrajectoryFile(*a.trajectory_path);
    if (!poses) return Fail(poses.error(), kExitFailure);
    o->room_map = std::move(*map);
    o->mount = *mount;
    o->base_trajectory = std::move(*poses);
  } else if (a.trajectory_path) {
    auto poses = ReadTrajectoryFile(*a.trajectory_path);
    if (!poses) return Fail(poses.error(), kExitUsage);
    o->trajectory = *poses;
  }
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

}  // namespace

int SimcamCommand(const std::vector<std::string>& argv) {
  SimcamArgs a;
  CommandLine line("simcam", kAbout);
  DeclareSimcam(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  SimCameraOptions& o = a.options;
  o.scene = a.scene == "corner" ? SimScene::kCorner
            : a.scene == "room" ? SimScene::kRoom
                                : SimScene::kFloor;
  if (o.raw && !o.realistic)
    return Fail("--raw goes with --realistic (the clean look is not compressed)", kExitUsage);
  o.look_seed = static_cast<uint64_t>(a.look_seed);
  if (int status = LoadScene(a, &o); status != kExitOk) return status;

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
  if (const auto& truth = a.truth_path) {
    if (auto w = WriteTruth(o, **cam, *truth); !w) return Fail(w.error(), kExitFailure);
  }
  if (const auto& cal_out = a.calibration_out) {
    if (auto w = WriteSimCalibration(o, **cam, *cal_out); !w) return Fail(w.error(), kExitFailure);
  }
  std::cerr << "serving simulated GigE Vision camera '" << o.serial << "' on " << o.ip << " ("
            << o.width << "x" << o.height << " Mono8, " << o.fps << " fps, scene " << a.scene
            << "); Ctrl-C stops\n";
  int signal = 0;
  sigwait(&stop, &signal);
  std::cerr << "stopping\n";
  return kExitOk;
}

}  // namespace monocle::cli
