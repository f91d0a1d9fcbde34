// monocle render floor | corner: our own renderers of a chessboard (and boxes) on the floor
// and of a ceiling corner.
#include <iostream>

#include "camera/render/corner_renderer.h"
#include "camera/render/floor_renderer.h"
#include "client/cli/args.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/shared_options.h"
#include "service/io/calibration_file.h"
#include "service/vision/chessboard.h"

namespace monocle::cli {
namespace {

// --noise SIGMA and --seed N, as every renderer takes them.
void DeclareNoise(CommandLine& line, double* noise, int* seed) {
  line.Number("--noise", noise, "SIGMA", "Gaussian noise", In("grey levels").AtLeast(0));
  line.Whole("--seed", seed, "N", "the noise's seed", In("").AtLeast(0));
}

struct RenderCornerArgs {
  std::string calibration_path, out_path;
  std::optional<CornerPose> pose;
  double noise = 0;
  int seed = 1;
  bool clutter = false, lighting = false, realistic = false, raw = false;
};

void DeclareRenderCorner(CommandLine& line, RenderCornerArgs* a) {
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "the camera: intrinsics, with distortion");
  line.Require("--calibration");
  line.Parsed<CornerPose>(
      "--pose", &a->pose, "X,Y,Z,PAN,TILT,SWING",
      "the camera's pose in the corner frame: metres (> 0) and radians",
      [](const std::string& text) -> Result<CornerPose> {
        const auto v = ParseNumberList(text);
        if (!v || v->size() != 6 || (*v)[0] <= 0 || (*v)[1] <= 0 || (*v)[2] <= 0) {
          return MakeError(ErrorCode::kInvalidArgument,
                           "'" + text + "' is not X,Y,Z,PAN,TILT,SWING (metres > 0, radians)");
        }
        return CornerPose{(*v)[0], (*v)[1], (*v)[2], (*v)[3], (*v)[4], (*v)[5]};
      });
  line.Require("--pose");
  line.Text("--out", &a->out_path, "IMG.png", "the image to write (.png, .jpg or .pgm)");
  line.Require("--out");
  DeclareNoise(line, &a->noise, &a->seed);
  line.Flag("--clutter", &a->clutter,
            "a lamp, a door frame, a ceiling fixture, a cable and a "
            "picture");
  line.Flag("--lighting", &a->lighting, "uneven lighting (a lamp's falloff) and a soft texture");
  line.Flag("--realistic", &a->realistic,
            "a white-painted room as a camera photographs it: ceiling and walls 10-40 grey "
            "levels apart (the wall-wall edge from 8), shading across each surface, a lamp "
            "hot-spot, vignetting up to 30 %, defocus blur sigma 0.7-1.6 px, sensor noise sigma "
            "2-4, JPEG quality 70-90, all drawn from --seed (the look is printed); --noise, "
            "--clutter, --lighting are ignored");
  line.Flag("--raw", &a->raw,
            "with --realistic: no JPEG step, as a machine-vision camera (GigE Vision, USB3 "
            "Vision) delivers its frames");
}

int RenderCorner(const std::vector<std::string>& argv) {
  RenderCornerArgs a;
  CommandLine line(
      "render corner",
      "Renders the 8-bit grey image the camera of CAL.pbtxt (intrinsics, with distortion) sees\n"
      "of a room corner from the given pose in the corner frame (metres and radians, as\n"
      "`monocle corner locate` reports it; Z is the camera-to-ceiling distance). The ceiling and\n"
      "the two walls are lit differently.");
  DeclareRenderCorner(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  if (a.raw && !a.realistic)
    return Fail("--raw goes with --realistic (the other looks are not compressed)", kExitUsage);
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  CornerScene scene;
  scene.clutter = a.clutter;
  scene.uneven_lighting = a.lighting;
  scene.noise_sigma = a.noise;
  scene.seed = static_cast<uint64_t>(a.seed);
  scene.room_height_m = std::max(scene.room_height_m, a.pose->z_m + 0.3);
  if (a.realistic) {
    scene.realistic = RandomRealisticLook(scene.seed, calibration->intrinsics);
    if (a.raw) scene.realistic->jpeg_quality = 0;
    std::cout << *scene.realistic << "\n";
  }
  const cv::Mat image = RenderCornerScene(calibration->intrinsics, *a.pose, scene);
  if (auto written = WriteImage(a.out_path, image); !written)
    return Fail(written.error(), kExitFailure);
  return kExitOk;
}

struct RenderFloorArgs {
  std::string calibration_path, out_path;
  BoardOptions board;
  double noise = 0;
  int seed = 1;
  std::optional<Eigen::Vector2d> board_origin;
  std::vector<FloorBox> boxes;
};

void DeclareRenderFloor(CommandLine& line, RenderFloorArgs* a) {
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "the camera: intrinsics and floor section (height, pitch, yaw, roll)");
  line.Require("--calibration");
  DeclareBoard(line, &a->board);
  line.Text("--out", &a->out_path, "IMG.png", "the image to write (.png, .jpg or .pgm)");
  line.Require("--out");
  DeclareNoise(line, &a->noise, &a->seed);
  line.Parsed<Eigen::Vector2d>(
      "--board-origin", &a->board_origin, "X,Y",
      "robot-frame floor position of inner corner (0,0), metres (default: the board is centred "
      "where the optical axis meets the floor); the board's x_p axis is turned by the file's "
      "yaw against X_w (eq. 10 of Xu et al.)",
      [](const std::string& text) -> Result<Eigen::Vector2d> {
        const auto xy = ParseNumberList(text);
        if (!xy || xy->size() != 2)
          return MakeError(ErrorCode::kInvalidArgument, "'" + text + "' is not X,Y in metres");
        return Eigen::Vector2d((*xy)[0], (*xy)[1]);
      });
  line.CustomRepeated(
      "--box", "X,Y,W,D,H",
      "a box standing on the floor: centre X,Y, width along X_w, depth along Y_w, height "
      "(metres)",
      [a](const std::string& text) -> std::optional<std::string> {
        const auto v = ParseNumberList(text);
        if (!v || v->size() != 5 || (*v)[2] <= 0 || (*v)[3] <= 0 || (*v)[4] <= 0)
          return "'" + text + "' is not X,Y,W,D,H in metres (W, D, H > 0)";
        a->boxes.push_back(FloorBox{{(*v)[0], (*v)[1]}, {(*v)[2], (*v)[3]}, (*v)[4]});
        return std::nullopt;
      });
}

int RenderFloor(const std::vector<std::string>& argv) {
  RenderFloorArgs a;
  CommandLine line(
      "render floor",
      "Renders the 8-bit grey image the camera of CAL.pbtxt (intrinsics and floor section: "
      "height,\npitch, yaw, roll) sees of a chessboard lying on the floor, as ground truth for "
      "tests and\nthe simulated floor camera.");
  DeclareRenderFloor(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) {
    return Fail(
        a.calibration_path + " has no floor section (height, pitch, yaw, roll) to render from",
        kExitFailure);
  }
  const FloorPose& pose = calibration->floor->pose;
  const BoardSpec spec = a.board.Spec();
  FloorScene scene;
  scene.board_cols = spec.cols;
  scene.board_rows = spec.rows;
  scene.square_m = spec.square_m;
  scene.noise_sigma = a.noise;
  scene.seed = static_cast<uint64_t>(a.seed);
  scene.board_origin_robot_m =
      a.board_origin.value_or(CenteredBoardOrigin(pose, spec.cols, spec.rows, spec.square_m));
  scene.boxes = a.boxes;
  const cv::Mat image = RenderFloorScene(calibration->intrinsics, pose, scene);
  if (auto written = WriteImage(a.out_path, image); !written)
    return Fail(written.error(), kExitFailure);
  return kExitOk;
}

}  // namespace

int RenderCommand(const std::vector<std::string>& argv) {
  if (!argv.empty() && argv[0] == "corner") return RenderCorner({argv.begin() + 1, argv.end()});
  if (!argv.empty() && argv[0] == "boards") return RenderBoards({argv.begin() + 1, argv.end()});
  if (!argv.empty() && argv[0] == "room") return RenderRoom({argv.begin() + 1, argv.end()});
  constexpr const char* kOverview =
      "Usage: monocle render floor|corner|room|boards ...\n\n"
      "  floor    a chessboard (and boxes) on the floor, as a floor camera sees it\n"
      "  corner   a ceiling corner, as a corner camera sees it (clean, cluttered, realistic)\n"
      "  room     a room of a map, as the robot's camera sees it at a pose or along a drive\n"
      "  boards   a set of chessboard views for intrinsics calibration\n\n"
      "monocle render COMMAND --help for each command's options.\n";
  if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
    (argv.empty() ? std::cerr : std::cout) << kOverview;
    return argv.empty() ? kExitUsage : kExitOk;
  }
  if (argv[0] != "floor") {
    return Fail("unknown render command '" + argv[0] + "' (floor, corner, room, boards)",
                kExitUsage);
  }
  return RenderFloor({argv.begin() + 1, argv.end()});
}

}  // namespace monocle::cli
