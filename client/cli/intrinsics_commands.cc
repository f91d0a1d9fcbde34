// monocle intrinsics calibrate: OpenCV's calibrateCamera over several board images.
#include <iomanip>
#include <iostream>
#include <opencv2/calib3d.hpp>

#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "service/io/calibration_file.h"
#include "service/vision/chessboard.h"

namespace monocle::cli {
namespace {

constexpr const char* kHelp =
    R"(Usage: monocle intrinsics calibrate IMAGE... --board COLSxROWS --square METRES --out CAL.pbtxt

Calibrates focal lengths (fx, fy, pixels), principal point (cx, cy, pixels) and lens
distortion (k1 k2 p1 p2, OpenCV's model) from several images of a chessboard seen from
different angles (at least 3; 10 or more tilted views are better). Writes CAL.pbtxt
atomically; an existing floor or corner section in CAL.pbtxt is kept.

  --board COLSxROWS  inner corners of the board, e.g. 9x6 (required)
  --square METRES    side of one square, metres (required)
  --out CAL.pbtxt    calibration file to write (required)
)";

}  // namespace

int IntrinsicsCommand(const std::vector<std::string>& argv) {
  if (argv.empty() || argv[0] != "calibrate" || WantsHelp(argv)) {
    std::cout << kHelp;
    return WantsHelp(argv) ? kExitOk : kExitUsage;
  }
  auto args = Args::Parse({argv.begin() + 1, argv.end()}, {{"--board", "--square", "--out"}, {}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto out_path = args->Require("--out");
  if (!out_path) return Fail(out_path.error(), kExitUsage);
  const auto spec = RequireBoard(*args);
  if (!spec) return Fail(spec.error(), kExitUsage);
  if (args->positionals().size() < 3)
    return Fail("give at least 3 board images (see --help)", kExitUsage);

  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  cv::Size size;
  for (const auto& path : args->positionals()) {
    const auto image = ReadGreyImage(path);
    if (!image) return Fail(image.error(), kExitFailure);
    if (size.area() == 0) size = image->size();
    if (image->size() != size)
      return Fail("image '" + path + "' differs in size from the first image", kExitFailure);
    const auto board = DetectChessboard(*image, *spec);
    if (!board) {
      std::cerr << "monocle: warning: " << path << ": " << board.error().message << "; skipped\n";
      continue;
    }
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (int j = 0; j < board->rows; ++j) {
      for (int i = 0; i < board->cols; ++i) {
        const auto p = board->BoardPoint(i, j);
        obj.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
        const auto& px = board->Pixel(i, j);
        img.emplace_back(static_cast<float>(px.x()), static_cast<float>(px.y()));
      }
    }
    object_points.push_back(std::move(obj));
    image_points.push_back(std::move(img));
  }
  if (image_points.size() < 3) {
    return Fail("the board was found in only " + std::to_string(image_points.size()) +
                    " images; at least 3 are needed",
                kExitFailure);
  }
  cv::Mat camera_matrix, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCamera(object_points, image_points, size, camera_matrix, dist,
                                         rvecs, tvecs, cv::CALIB_FIX_K3);
  CameraCalibration cal;
  if (auto existing = LoadCalibrationFile(*out_path); existing) cal = *existing;
  auto& k = cal.intrinsics;
  k.width_px = size.width;
  k.height_px = size.height;
  k.fx = camera_matrix.at<double>(0, 0);
  k.fy = camera_matrix.at<double>(1, 1);
  k.cx = camera_matrix.at<double>(0, 2);
  k.cy = camera_matrix.at<double>(1, 2);
  k.distortion = {};
  for (int i = 0; i < 4; ++i) k.distortion[i] = dist.at<double>(i);
  cal.intrinsics_rms_px = rms;
  const auto saved = SaveCalibrationFileAtomically(*out_path, cal);
  if (!saved) return Fail(saved.error(), kExitFailure);
  std::cout << std::setprecision(8) << "images  " << image_points.size() << "\nfx fy   " << k.fx
            << " " << k.fy << " px\ncx cy   " << k.cx << " " << k.cy << " px\ndist    "
            << k.distortion[0] << " " << k.distortion[1] << " " << k.distortion[2] << " "
            << k.distortion[3] << "\nrms     " << rms << " px\nwritten to " << *out_path << "\n";
  return kExitOk;
}

}  // namespace monocle::cli
