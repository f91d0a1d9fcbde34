// monocle render boards: views of a chessboard held in front of the camera of a calibration
// file, for trying and testing intrinsic calibration against known intrinsics.
#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "camera/render/board_renderer.h"
#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "client/cli/progress.h"
#include "service/io/calibration_file.h"

namespace monocle::cli {
namespace {

constexpr const char* kHelp =
    R"(Usage: monocle render boards --calibration CAL.pbtxt --board COLSxROWS --square METRES
                             --views N --out-dir DIR [--seed N] [--spread good|fronto|corner]
                             [--clean]

Renders N images of a chessboard held in front of the camera of CAL.pbtxt (its intrinsics,
with distortion), as DIR/view-01.png ..., for `monocle intrinsics calibrate`: the truth is
CAL.pbtxt. Each view is photographed as a real one is: uneven light, vignetting, blur
sigma 0.5-1.2 px, noise sigma 1-3 grey levels, JPEG quality 80-95 (drawn from --seed).

  --spread good    near every corner and edge of the image, tilted 15-40 degrees (default)
  --spread fronto  facing the camera (tilt < 3 degrees): a badly posed set
  --spread corner  always in the image's top-left quarter: a badly posed set
  --clean          no blur, noise, JPEG or uneven light
  --seed N         poses and looks (default 1)
)";

}  // namespace

int RenderBoards(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kHelp;
    return kExitOk;
  }
  auto args = Args::Parse(
      argv, {{"--calibration", "--board", "--square", "--views", "--out-dir", "--seed", "--spread"},
             {"--clean"}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const auto dir = args->Require("--out-dir");
  if (!dir) return Fail(dir.error(), kExitUsage);
  const auto spec = RequireBoard(*args);
  if (!spec) return Fail(spec.error(), kExitUsage);
  const auto count = args->RequireDouble("--views");
  if (!count || *count < 1 || *count > 1000 || *count != std::floor(*count))
    return Fail("--views must be a whole number 1..1000", kExitUsage);
  const auto seed = args->GetDouble("--seed", 1.0);
  if (!seed || *seed < 0) return Fail("--seed must be a whole number >= 0", kExitUsage);
  const std::string spread_text = args->Get("--spread").value_or("good");
  ViewSpread spread;
  if (spread_text == "good") {
    spread = ViewSpread::kGood;
  } else if (spread_text == "fronto") {
    spread = ViewSpread::kFrontoParallel;
  } else if (spread_text == "corner") {
    spread = ViewSpread::kOneCorner;
  } else {
    return Fail("--spread '" + spread_text + "' is not good, fronto or corner", kExitUsage);
  }
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  std::error_code ec;
  std::filesystem::create_directories(*dir, ec);
  if (ec) return Fail("cannot create '" + *dir + "': " + ec.message(), kExitFailure);

  const auto& k = calibration->intrinsics;
  const CheckerPattern base{spec->cols, spec->rows, spec->square_m};
  const auto base_seed = static_cast<uint64_t>(*seed);
  const auto poses = RandomBoardViews(k, base, static_cast<int>(*count), base_seed, spread);
  if (poses.size() < static_cast<size_t>(*count)) {
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
    if (!args->Has("--clean")) look = RandomBoardLook(base_seed * 1000 + i, k, &pattern);
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
