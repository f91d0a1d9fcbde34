// monocle render boards: views of a chessboard held in front of the camera of a calibration
// file, for trying and testing intrinsic calibration against known intrinsics.
#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "camera/render/board_renderer.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/progress.h"
#include "client/cli/shared_options.h"
#include "service/io/calibration_file.h"

namespace monocle::cli {
namespace {

struct RenderBoardsArgs {
  std::string calibration_path, dir;
  BoardOptions board;
  int count = 0;
  int seed = 1;
  std::string spread = "good";
  bool clean = false;
};

void DeclareRenderBoards(CommandLine& line, RenderBoardsArgs* a) {
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "the camera: its intrinsics, with distortion, are the truth");
  line.Require("--calibration");
  DeclareBoard(line, &a->board);
  line.Whole("--views", &a->count, "N", "how many views", In("views").Between(1, 1000));
  line.Require("--views");
  line.Text("--out-dir", &a->dir, "DIR", "where DIR/view-01.png ... go");
  line.Require("--out-dir");
  line.Whole("--seed", &a->seed, "N", "the poses' and looks' seed", In("").AtLeast(0));
  line.Choice("--spread", &a->spread, {"good", "fronto", "corner"},
              "good: near every corner and edge of the image, tilted 15-40 degrees; fronto: "
              "facing the camera (tilt < 3 degrees), a badly posed set; corner: always in the "
              "image's top-left quarter, a badly posed set");
  line.Flag("--clean", &a->clean, "no blur, noise, JPEG or uneven light");
}

}  // namespace

int RenderBoards(const std::vector<std::string>& argv) {
  RenderBoardsArgs a;
  CommandLine line(
      "render boards",
      "Renders N images of a chessboard held in front of the camera of CAL.pbtxt (its "
      "intrinsics,\nwith distortion), as DIR/view-01.png ..., for `monocle intrinsics calibrate`: "
      "the truth is\nCAL.pbtxt. Each view is photographed as a real one is: uneven light, "
      "vignetting, blur\nsigma 0.5-1.2 px, noise sigma 1-3 grey levels, JPEG quality 80-95 (drawn "
      "from --seed).");
  DeclareRenderBoards(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const ViewSpread spread = a.spread == "fronto"   ? ViewSpread::kFrontoParallel
                            : a.spread == "corner" ? ViewSpread::kOneCorner
                                                   : ViewSpread::kGood;
  const std::string* dir = &a.dir;
  const BoardSpec board = a.board.Spec();
  const BoardSpec* spec = &board;
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  std::error_code ec;
  std::filesystem::create_directories(*dir, ec);
  if (ec) return Fail("cannot create '" + *dir + "': " + ec.message(), kExitFailure);

  const auto& k = calibration->intrinsics;
  const CheckerPattern base{spec->cols, spec->rows, spec->square_m};
  const auto base_seed = static_cast<uint64_t>(a.seed);
  const auto poses = RandomBoardViews(k, base, a.count, base_seed, spread);
  if (poses.size() < static_cast<size_t>(a.count)) {
    return Fail("only " + std::to_string(poses.size()) + " views of a " +
                    std::to_string(spec->cols) + "x" + std::to_string(spec->rows) +
                    " board fit the image; use a smaller board",
                kExitFailure);
  }
  ProgressLine progress("rendering views", poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    progress.Update(i);
    CheckerPattern pattern = base;
    BoardLook look;
    if (!a.clean) look = RandomBoardLook(base_seed * 1000 + i, k, &pattern);
    std::ostringstream name;
    name << *dir << "/view-" << std::setw(2) << std::setfill('0') << i + 1 << ".png";
    const cv::Mat image = RenderBoardView(k, poses[i], pattern, look, base_seed * 1000 + i);
    if (auto w = WriteImage(name.str(), image); !w) return Fail(w.error(), kExitFailure);
  }
  progress.Done();
  std::cout << "wrote " << poses.size() << " views to " << *dir << "\n";
  return kExitOk;
}

}  // namespace monocle::cli
