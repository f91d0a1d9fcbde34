// monocle render room: what the robot's camera sees inside a room of a map, at one base pose or
// along a trajectory (ground truth for `corner locate --map` and the room tests).
#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numbers>

#include "camera/render/room_renderer.h"
#include "client/cli/args.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/progress.h"
#include "service/io/base_trajectory_file.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"

namespace monocle::cli {
namespace {

constexpr const char* kAbout =
    R"(Renders what the camera of CAL.pbtxt (intrinsics, with distortion), mounted on the robot as
MOUNT.pbtxt says, sees inside the room of MAP.pbtxt where the robot stands: the ceiling, every
wall of the room's outline and the floor, so corners come into and out of view as it drives.)";

constexpr const char* kFooter =
    R"(The trajectory file is the ground truth of the images: compare `monocle corner locate
DIR/*.png --map MAP --mount MOUNT --track --prior <its first line>` against it, or draw both
with `monocle map draw MAP --trajectory FILE --poses POSES.jsonl`.)";

struct RenderRoomArgs {
  std::string map_path, mount_path, calibration_path, out;
  std::optional<BasePose2d> pose;
  std::optional<std::string> trajectory_path;
  bool realistic = false, raw = false;
  int seed = 1;
};

void DeclareRenderRoom(CommandLine& line, RenderRoomArgs* a) {
  line.Footer(kFooter);
  line.Text("--map", &a->map_path, "MAP.pbtxt", "the rooms (idl/room_map.proto)");
  line.Require("--map");
  line.Text("--mount", &a->mount_path, "MOUNT.pbtxt", "the camera's pose on the robot base");
  line.Require("--mount");
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt", "the camera's intrinsics");
  line.Require("--calibration");
  line.Text("--out", &a->out, "IMG.png|DIR",
            "the image (with --pose), or the folder of DIR/frame_0000.png, ... (with "
            "--trajectory)");
  line.Require("--out");
  line.Flag("--realistic", &a->realistic,
            "a white-painted room as a camera photographs it (the look of `render corner "
            "--realistic`: low contrast, shading, hot-spot, vignetting, blur, noise, JPEG), "
            "drawn from the seed; without it, clean flat greys");
  line.Flag("--raw", &a->raw,
            "with --realistic: no JPEG step, as a machine-vision camera delivers its frames");
  line.Whole("--seed", &a->seed, "N",
             "the look's and the noise's seed; frame k of a trajectory uses N + k",
             In("").AtLeast(0));
  line.InForms({0});
  line.Parsed<BasePose2d>(
      "--pose", &a->pose, "X,Y,HEADING_DEG",
      "the robot base in the map frame: metres, and degrees from the map's +x towards +y; one "
      "image",
      [](const std::string& text) -> Result<BasePose2d> {
        const auto v = ParseNumberList(text);
        if (!v || v->size() != 3) {
          return MakeError(ErrorCode::kInvalidArgument,
                           "'" + text + "' is not X,Y,HEADING_DEG (metres, degrees)");
        }
        return BasePose2d{(*v)[0], (*v)[1], (*v)[2] * std::numbers::pi / 180};
      });
  line.Require("--pose");
  line.Form("Along a drive, instead of --pose");
  line.Text("--trajectory", &a->trajectory_path, "FILE",
            "one such pose a line (x_m y_m heading_deg, e.g. idl/examples/drive.txt); one image "
            "a pose, in its order");
  line.Require("--trajectory");
}

// The optical frame in the map: the base on the floor at `b`, then the mount. Built here with
// Eigen's AngleAxis, apart from the code the locator places poses in the map with.
Eigen::Isometry3d MapFromCamera(const BasePose2d& b, const RigidTransform& mount) {
  Eigen::Isometry3d map_base = Eigen::Isometry3d::Identity();
  map_base.translate(Eigen::Vector3d(b.x_m, b.y_m, 0));
  map_base.rotate(Eigen::AngleAxisd(b.heading_rad, Eigen::Vector3d::UnitZ()));
  Eigen::Isometry3d base_camera = Eigen::Isometry3d::Identity();
  base_camera.translate(mount.translation);
  base_camera.rotate(mount.rotation);
  return map_base * base_camera;
}

Result<cv::Mat> RenderAt(const CameraIntrinsics& k, const RoomMap& map, const RigidTransform& mount,
                         const BasePose2d& base, bool realistic, bool raw, uint64_t seed) {
  const Eigen::Isometry3d map_camera = MapFromCamera(base, mount);
  const MapRoom* room = RoomContaining(map, map_camera.translation().head<2>(), 0.01);
  if (room == nullptr) {
    std::ostringstream os;
    os << "the camera at (" << map_camera.translation().x() << ", " << map_camera.translation().y()
       << ") m, on the robot at " << base << ", stands in no room of the map";
    return MakeError(ErrorCode::kOutOfRange, os.str());
  }
  RoomScene scene;
  scene.seed = seed;
  if (realistic) scene.realistic = RandomRealisticLook(seed, k);
  if (realistic && raw) scene.realistic->jpeg_quality = 0;
  return RenderRoomView(k, *room, map_camera, scene);
}

}  // namespace

int RenderRoom(const std::vector<std::string>& argv) {
  RenderRoomArgs a;
  CommandLine line("render room", kAbout);
  DeclareRenderRoom(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  if (a.raw && !a.realistic)
    return Fail("--raw goes with --realistic (the clean look is not compressed)", kExitUsage);
  const bool many = a.trajectory_path.has_value();
  std::vector<BasePose2d> poses;
  if (a.pose) {
    poses.push_back(*a.pose);
  } else {
    auto trajectory = LoadBaseTrajectoryFile(*a.trajectory_path);
    if (!trajectory) return Fail(trajectory.error(), kExitFailure);
    poses = std::move(*trajectory);
  }
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  const auto map = LoadRoomMapFile(a.map_path);
  if (!map) return Fail(map.error(), kExitFailure);
  const auto mount = LoadCameraMountFile(a.mount_path, *map);
  if (!mount) return Fail(mount.error(), kExitFailure);
  const std::string& out = a.out;
  if (many) {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) return Fail("cannot create folder '" + out + "': " + ec.message(), kExitFailure);
  }
  ProgressLine progress("rendering", poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto image = RenderAt(calibration->intrinsics, *map, *mount, poses[i], a.realistic, a.raw,
                                static_cast<uint64_t>(a.seed) + i);
    if (!image) {
      return Fail(many ? "trajectory pose " + std::to_string(i + 1) + ": " + image.error().message
                       : image.error().message,
                  kExitFailure);
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    const std::string path = many ? (std::filesystem::path(out) / name).string() : out;
    if (auto written = WriteImage(path, *image); !written)
      return Fail(written.error(), kExitFailure);
    progress.Update(i + 1);
  }
  return kExitOk;
}

}  // namespace monocle::cli
