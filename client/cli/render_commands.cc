// monocle render floor: our own renderer of a chessboard (and boxes) on the floor.
#include <iostream>

#include "camera/render/corner_renderer.h"
#include "camera/render/floor_renderer.h"
#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "service/io/calibration_file.h"
#include "service/vision/chessboard.h"

namespace monocle::cli {
namespace {

constexpr const char* kHelp =
    R"(Usage: monocle render floor --calibration CAL.pbtxt --board COLSxROWS --square METRES --out IMG.png
                           [--noise SIGMA] [--seed N] [--board-origin X,Y] [--box X,Y,W,D,H]...

Renders the 8-bit grey image the camera of CAL.pbtxt (intrinsics and floor section: height,
pitch, yaw, roll) sees of a chessboard lying on the floor, as ground truth for tests and
the simulated floor camera.

  --board COLSxROWS  inner corners, e.g. 9x6; the board's x_p axis is turned by the
                     file's yaw against X_w (eq. 10 of Xu et al.)
  --square METRES    side of one square, metres
  --board-origin X,Y robot-frame floor position of inner corner (0,0), metres
                     (default: the board is centred where the optical axis meets the floor)
  --box X,Y,W,D,H    a box standing on the floor: centre X,Y, width along X_w, depth
                     along Y_w, height (metres); repeatable
  --noise SIGMA      Gaussian noise, grey levels (default 0)
  --seed N           noise seed (default 1)
  --out IMG.png      output image (.png, .jpg or .pgm)
)";

constexpr const char* kCornerHelp =
    R"(Usage: monocle render corner --calibration CAL.pbtxt --pose X,Y,Z,PAN,TILT,SWING --out IMG.png
                            [--noise SIGMA] [--seed N] [--clutter] [--lighting]
                            [--realistic [--raw]]

Renders the 8-bit grey image the camera of CAL.pbtxt (intrinsics, with distortion) sees
of a room corner from the given pose in the corner frame (metres and radians, as
`monocle corner locate` reports it; Z is the camera-to-ceiling distance). The ceiling and
the two walls are lit differently.

  --clutter        a lamp, a door frame, a ceiling fixture, a cable and a picture
  --lighting       uneven lighting (a lamp's falloff) and a soft texture
  --realistic      a white-painted room as a camera photographs it: ceiling and walls
                   10-40 grey levels apart (the wall-wall edge from 8), shading across each
                   surface, a lamp hot-spot, vignetting up to 30 %, defocus blur sigma
                   0.7-1.6 px, sensor noise sigma 2-4, JPEG quality 70-90, all drawn from
                   --seed (the look is printed); --noise, --clutter, --lighting are ignored
  --raw            with --realistic: no JPEG step, as a machine-vision camera (GigE Vision,
                   USB3 Vision) delivers its frames
  --noise SIGMA    Gaussian noise, grey levels (default 0); --seed N its seed (default 1)
)";

int RenderCorner(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kCornerHelp;
    return kExitOk;
  }
  auto args = Args::Parse(argv, {{"--calibration", "--pose", "--out", "--noise", "--seed"},
                                 {"--clutter", "--lighting", "--realistic", "--raw"}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (!args->positionals().empty())
    return Fail("unexpected argument '" + args->positionals()[0] + "'", kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const auto out_path = args->Require("--out");
  if (!out_path) return Fail(out_path.error(), kExitUsage);
  const auto pose_text = args->Require("--pose");
  if (!pose_text) return Fail(pose_text.error(), kExitUsage);
  const auto v = ParseNumberList(*pose_text);
  if (!v || v->size() != 6 || (*v)[0] <= 0 || (*v)[1] <= 0 || (*v)[2] <= 0) {
    return Fail("--pose '" + *pose_text + "' is not X,Y,Z,PAN,TILT,SWING (metres > 0, radians)",
                kExitUsage);
  }
  const auto noise = args->GetDouble("--noise", 0.0);
  if (!noise || *noise < 0) return Fail("--noise must be a number of grey levels >= 0", kExitUsage);
  const auto seed = args->GetDouble("--seed", 1.0);
  if (!seed || *seed < 0) return Fail("--seed must be a whole number >= 0", kExitUsage);
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  CornerScene scene;
  scene.clutter = args->Has("--clutter");
  scene.uneven_lighting = args->Has("--lighting");
  scene.noise_sigma = *noise;
  scene.seed = static_cast<uint64_t>(*seed);
  scene.room_height_m = std::max(scene.room_height_m, (*v)[2] + 0.3);
  if (args->Has("--raw") && !args->Has("--realistic"))
    return Fail("--raw goes with --realistic (the other looks are not compressed)", kExitUsage);
  if (args->Has("--realistic")) {
    scene.realistic = RandomRealisticLook(scene.seed, calibration->intrinsics);
    if (args->Has("--raw")) scene.realistic->jpeg_quality = 0;
    std::cout << *scene.realistic << "\n";
  }
  const CornerPose pose{(*v)[0], (*v)[1], (*v)[2], (*v)[3], (*v)[4], (*v)[5]};
  const cv::Mat image = RenderCornerScene(calibration->intrinsics, pose, scene);
  if (auto written = WriteImage(*out_path, image); !written)
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
  if (WantsHelp({argv.begin() + 1, argv.end()})) {
    std::cout << kHelp;
    return kExitOk;
  }
  auto args =
      Args::Parse({argv.begin() + 1, argv.end()}, {{"--calibration", "--board", "--square", "--out",
                                                    "--noise", "--seed", "--board-origin", "--box"},
                                                   {}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (!args->positionals().empty())
    return Fail("unexpected argument '" + args->positionals()[0] + "'", kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const auto out_path = args->Require("--out");
  if (!out_path) return Fail(out_path.error(), kExitUsage);
  const auto spec = RequireBoard(*args);
  if (!spec) return Fail(spec.error(), kExitUsage);
  const auto noise = args->GetDouble("--noise", 0.0);
  if (!noise || *noise < 0) return Fail("--noise must be a number of grey levels >= 0", kExitUsage);
  const auto seed = args->GetDouble("--seed", 1.0);
  if (!seed || *seed < 0) return Fail("--seed must be a whole number >= 0", kExitUsage);

  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) {
    return Fail(*cal_path + " has no floor section (height, pitch, yaw, roll) to render from",
                kExitFailure);
  }
  const FloorPose& pose = calibration->floor->pose;
  FloorScene scene;
  scene.board_cols = spec->cols;
  scene.board_rows = spec->rows;
  scene.square_m = spec->square_m;
  scene.noise_sigma = *noise;
  scene.seed = static_cast<uint64_t>(*seed);
  scene.board_origin_robot_m = CenteredBoardOrigin(pose, spec->cols, spec->rows, spec->square_m);
  if (const auto origin = args->Get("--board-origin")) {
    const auto xy = ParseNumberList(*origin);
    if (!xy || xy->size() != 2)
      return Fail("--board-origin '" + *origin + "' is not X,Y in metres", kExitUsage);
    scene.board_origin_robot_m = Eigen::Vector2d((*xy)[0], (*xy)[1]);
  }
  for (const auto& text : args->GetAll("--box")) {
    const auto v = ParseNumberList(text);
    if (!v || v->size() != 5 || (*v)[2] <= 0 || (*v)[3] <= 0 || (*v)[4] <= 0) {
      return Fail("--box '" + text + "' is not X,Y,W,D,H in metres (W, D, H > 0)", kExitUsage);
    }
    scene.boxes.push_back(FloorBox{{(*v)[0], (*v)[1]}, {(*v)[2], (*v)[3]}, (*v)[4]});
  }
  const cv::Mat image = RenderFloorScene(calibration->intrinsics, pose, scene);
  if (auto written = WriteImage(*out_path, image); !written)
    return Fail(written.error(), kExitFailure);
  return kExitOk;
}

}  // namespace monocle::cli
