// monocle intrinsics calibrate: the camera's intrinsics from several board images, each
// parameter with its 1 sigma, the views judged, and pictures of what was seen.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/progress.h"
#include "client/cli/shared_options.h"
#include "client/cli/uncertainty_picture.h"
#include "idl/cli_output.pb.h"
#include "service/geometry/projection_uncertainty.h"
#include "service/io/atomic_file.h"
#include "service/io/calibration_file.h"
#include "service/vision/chessboard.h"
#include "service/vision/intrinsic_calibration.h"

namespace monocle::cli {
namespace {

constexpr const char* kAbout =
    R"(Calibrates focal lengths (fx, fy, pixels), principal point (cx, cy, pixels) and lens
distortion (OpenCV's model) from images of a chessboard seen from different places and
angles, and reports how sure it is: each parameter with its 1 sigma (the full covariance
goes into CAL.pbtxt, and floor calibrations and measurements made with it include it). The
1 sigma counts what independent corner noise does not: with 5 views or more, each
parameter's analytic 1 sigma is raised to the spread of the fits that leave one view out
(jackknife) where that is larger; the JSON has both. It also says how sure the calibration
is of where a ray lands, across the image (--overlay draws it).

Good views: 10-20 images, the board near every corner and edge of the image and in its
middle, tilted 20-45 degrees in different directions, sharp and evenly lit.)";

constexpr const char* kFooter =
    R"(Warnings (on stderr, and in the JSON) say when the views do not constrain the model:
too few views (< 10), boards covering < 30 % of the image or missing its corners, no
tilt above 15 degrees, or a 1 sigma of fx above 0.3 % or of cx, cy above 0.3 % of the
image size.)";

struct IntrinsicsArgs {
  std::vector<std::string> images;
  BoardOptions board;
  std::string out_path;
  IntrinsicCalibrationOptions options;
  std::optional<std::string> overlay_dir;
  std::optional<std::string> corners_path;
  bool json = false;
};

void DeclareIntrinsics(CommandLine& line, IntrinsicsArgs* a) {
  line.Footer(kFooter);
  line.Positionals("IMAGE", &a->images, "a picture of the chessboard", 3);
  DeclareBoard(line, &a->board);
  line.Text("--out", &a->out_path, "CAL.pbtxt",
            "calibration file to write atomically. Its corner section is kept; a floor section "
            "is removed (it was fitted with the old intrinsics: calibrate the floor again)");
  line.Require("--out");
  line.Custom(
      "--model", "auto|k1k2|k1k2p1p2|k1k2p1p2k3",
      "distortion model: k1k2 (radial), k1k2p1p2 (+ tangential), k1k2p1p2k3 (+ a third "
      "radial term, wide-angle lenses), or auto (default): the smallest model that predicts "
      "each view left out of the fit as well as the best does (within one standard "
      "error; by BIC below 5 views); the choice and its reason are printed",
      [a](const std::string& text) -> std::optional<std::string> {
        const auto model = ParseDistortionModel(text);
        if (!model) return model.error().message;
        a->options.model = *model;
        return std::nullopt;
      });
  line.Flag("--drop-outliers", &a->options.drop_outliers,
            "refit without the views whose RMS exceeds 3x the median view's (they are always "
            "named)");
  line.Text("--overlay", &a->overlay_dir, "DIR",
            "write DIR/<image>.png per view (detected corners, each corner's residual magnified "
            "100x as a red line, corners left out as blunders as red circles) and "
            "DIR/coverage.png (where in the image corners were seen) and DIR/uncertainty.png "
            "(the 1 sigma of where a ray lands across the image, with the corners seen: where "
            "to hold the board next)");
  line.Text("--corners", &a->corners_path, "FILE.vnl",
            "write the corners used, in mrcal's corners.vnl format (filename x y level; "
            "corners left out as blunders are '-'), to fit the same corners with mrcal");
  line.Flag("--json", &a->json, "print one JSON object (idl/cli_output.proto IntrinsicsOutput)");
}

constexpr double kResidualMagnification = 100;

// "\rdetecting boards 12/55" on a terminal, nothing otherwise.
cv::Mat ToColour(const cv::Mat& grey) {
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  return colour;
}

cv::Point2d P(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }

void DrawView(cv::Mat& image, const BoardObservation& board, const ViewFit& fit) {
  // Residuals are listed for the corners used, in order; rejected corners (drawn in red,
  // without a residual) are skipped.
  size_t next = 0;
  for (size_t i = 0; i < board.pixels.size(); ++i) {
    const auto& px = board.pixels[i];
    const bool rejected = std::find(fit.rejected_indices.begin(), fit.rejected_indices.end(),
                                    static_cast<int>(i)) != fit.rejected_indices.end();
    cv::circle(image, P(px), rejected ? 6 : 3,
               rejected ? cv::Scalar(0, 0, 255) : cv::Scalar(0, 200, 0), 1, cv::LINE_AA);
    if (rejected || next >= fit.residuals_px.size()) continue;
    cv::line(image, P(px), P(px + kResidualMagnification * fit.residuals_px[next]),
             cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    ++next;
  }
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << fit.name << "  RMS " << fit.rms_px << " px  tilt "
       << std::setprecision(0) << fit.tilt_deg << " deg" << (fit.outlier ? "  OUTLIER" : "")
       << "   red: residual x100";
  cv::putText(image, text.str(), {10, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 3,
              cv::LINE_AA);
  cv::putText(image, text.str(), {10, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
              fit.outlier ? cv::Scalar(0, 0, 255) : cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
}

cv::Mat CoveragePicture(const cv::Size& size, const std::vector<IntrinsicView>& views,
                        const IntrinsicCalibration& cal) {
  cv::Mat picture(size, CV_8UC3, cv::Scalar(40, 40, 40));
  for (size_t v = 0; v < views.size(); ++v) {
    const auto& b = views[v].board;
    const cv::Scalar colour(80 + (v * 67) % 176, 80 + (v * 131) % 176, 80 + (v * 197) % 176);
    std::vector<cv::Point> outline;
    for (const auto& [i, j] :
         {std::pair{0, 0}, {b.cols - 1, 0}, {b.cols - 1, b.rows - 1}, {0, b.rows - 1}})
      outline.emplace_back(P(b.Pixel(i, j)));
    cv::polylines(picture, outline, true, colour, 1, cv::LINE_AA);
    for (const auto& px : b.pixels) cv::circle(picture, P(px), 2, colour, cv::FILLED);
  }
  std::ostringstream text;
  text << "corners of " << views.size() << " views: boards cover " << std::fixed
       << std::setprecision(0) << 100 * cal.coverage << " % of the image";
  cv::putText(picture, text.str(), {10, size.height - 12}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  return picture;
}

std::string Stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// The boards found in the images; views without one are listed in `out` with the reason.
// kExitOk, or the exit status of an unreadable image or one of another size.
int DetectBoards(const std::vector<std::string>& paths, const BoardSpec& spec,
                 proto::IntrinsicsOutput* out, std::vector<IntrinsicView>* views, cv::Size* size) {
  ProgressLine progress("detecting boards", paths.size());
  for (size_t n = 0; n < paths.size(); ++n) {
    progress.Update(n);
    const auto& path = paths[n];
    const auto image = ReadGreyImage(path);
    if (!image) return Fail(image.error(), kExitFailure);
    if (size->area() == 0) *size = image->size();
    if (image->size() != *size)
      return Fail("image '" + path + "' differs in size from the first image", kExitFailure);
    auto board = DetectChessboard(*image, spec);
    if (!board) {
      progress.Done();
      std::cerr << "monocle: warning: " << path << ": " << board.error().message << "; skipped\n";
      auto* v = out->add_views();
      v->set_image(path);
      v->set_error(board.error().message);
      continue;
    }
    views->push_back({path, std::move(*board)});
  }
  progress.Done();
  return kExitOk;
}

// The cell size of the projection uncertainty reported and drawn, px.
constexpr double kProjectionCellPx = 8;

// Each view with its corners and their residuals, the image's coverage and the projection
// uncertainty, into `dir`.
Status WriteOverlays(const std::string& dir, const std::vector<IntrinsicView>& views,
                     const IntrinsicCalibration& cal, cv::Size size) {
  for (const auto& fit : cal.views) {
    const auto it = std::find_if(views.begin(), views.end(),
                                 [&](const IntrinsicView& v) { return v.name == fit.name; });
    const auto image = ReadGreyImage(fit.name);
    if (it == views.end() || !image) continue;
    cv::Mat colour = ToColour(*image);
    DrawView(colour, it->board, fit);
    if (auto w = WriteImage(dir + "/" + Stem(fit.name) + ".png", colour); !w) return w;
  }
  if (auto w = WriteImage(dir + "/coverage.png", CoveragePicture(size, views, cal)); !w) return w;
  const auto map = MapProjectionUncertainty(cal.intrinsics, cal.covariance, kProjectionCellPx);
  return WriteImage(dir + "/uncertainty.png", ProjectionUncertaintyPicture(map, size, views));
}

// The corners as mrcal reads them (corners.vnl: one line per board corner, row by row, the
// image's file name, x y, and a weight level or '-' for a corner not used). The detector may
// find a board turned by a quarter (6x9 instead of 9x6); mrcal needs one layout, so every
// view is written with its longer side along the rows (--object-width-n is the larger count).
Status WriteMrcalCorners(const std::string& path, const std::vector<IntrinsicView>& views,
                         const IntrinsicCalibration& cal) {
  std::ostringstream vnl;
  vnl << std::setprecision(9) << "# filename x y level\n";
  for (const auto& view : views) {
    const auto fit = std::find_if(cal.views.begin(), cal.views.end(),
                                  [&](const ViewFit& f) { return f.name == view.name; });
    if (fit == cal.views.end()) continue;
    const auto& b = view.board;
    const bool transposed = b.rows > b.cols;
    const int width = std::max(b.cols, b.rows), height = std::min(b.cols, b.rows);
    for (int row = 0; row < height; ++row) {
      for (int col = 0; col < width; ++col) {
        const int i = transposed ? row : col, j = transposed ? col : row;
        const bool used = std::find(fit->rejected_indices.begin(), fit->rejected_indices.end(),
                                    j * b.cols + i) == fit->rejected_indices.end();
        vnl << std::filesystem::path(view.name).filename().string() << " ";
        if (used) {
          vnl << b.Pixel(i, j).x() << " " << b.Pixel(i, j).y() << " 0\n";
        } else {
          vnl << "- - -\n";
        }
      }
    }
  }
  return WriteFileAtomically(path, vnl.str());
}

void SetSigma(const Eigen::Matrix<double, kNumIntrinsicParams, 1>& sigma,
              proto::IntrinsicsSigma* s) {
  s->set_fx(sigma[0]);
  s->set_fy(sigma[1]);
  s->set_cx(sigma[2]);
  s->set_cy(sigma[3]);
  for (int i = 0; i < 5; ++i) s->add_distortion(sigma[4 + i]);
}

void SetProjectionSigma(const ProjectionUncertaintyMap::Summary& s, proto::ProjectionSigma* out) {
  out->set_centre_px(s.centre_px);
  out->set_median_px(s.median_px);
  out->set_worst_px(s.worst_px);
  out->set_worst_x(s.worst_at_px.x());
  out->set_worst_y(s.worst_at_px.y());
}

// The result as the JSON output has it.
void FillOutput(const IntrinsicCalibration& cal, const std::string& written, bool floor_removed,
                proto::IntrinsicsOutput* out) {
  const auto& k = cal.intrinsics;
  const auto sigma = cal.Sigma();
  out->set_width(k.width_px);
  out->set_height(k.height_px);
  out->set_fx(k.fx);
  out->set_fy(k.fy);
  out->set_cx(k.cx);
  out->set_cy(k.cy);
  for (int i = 0; i < 5; ++i) out->add_distortion(k.distortion[i]);
  SetSigma(sigma, out->mutable_sigma());
  SetSigma(cal.analytic_covariance.diagonal().cwiseMax(0).cwiseSqrt(),
           out->mutable_analytic_sigma());
  SetSigma(cal.jackknife_covariance.diagonal().cwiseMax(0).cwiseSqrt(),
           out->mutable_jackknife_sigma());
  out->set_covariance_method(cal.covariance_method);
  const auto map = MapProjectionUncertainty(k, cal.covariance, kProjectionCellPx);
  SetProjectionSigma(map.absolute, out->mutable_projection_sigma());
  SetProjectionSigma(map.relative, out->mutable_relative_projection_sigma());
  for (const auto& trial : cal.trials) {
    auto* t = out->add_trials();
    t->set_model(ToString(trial.model));
    t->set_rms_px(trial.rms_px);
    t->set_held_out_rms_px(trial.held_out_rms_px);
    t->set_bic(trial.bic);
  }
  out->set_model(ToString(cal.model));
  out->set_model_reason(cal.model_reason);
  out->set_rms_px(cal.rms_px);
  out->set_corner_sigma_px(cal.corner_sigma_px);
  out->set_coverage(cal.coverage);
  out->set_max_tilt_deg(cal.max_tilt_deg);
  for (const auto& fit : cal.views) {
    auto* v = out->add_views();
    v->set_image(fit.name);
    v->set_rms_px(fit.rms_px);
    v->set_tilt_deg(fit.tilt_deg);
    v->set_outlier(fit.outlier);
    v->set_dropped(fit.dropped);
    v->set_rejected_corners(fit.rejected_corners);
  }
  for (const auto& w : cal.warnings) out->add_warnings(w);
  out->set_written(written);
  out->set_floor_removed(floor_removed);
}

void PrintWarnings(const IntrinsicCalibration& cal, const std::string& written,
                   bool floor_removed) {
  for (const auto& w : cal.warnings) std::cerr << "monocle: warning: " << w << "\n";
  for (const auto& fit : cal.views) {
    if (fit.outlier && !fit.dropped) {
      std::cerr << "monocle: warning: view " << fit.name << " is an outlier (RMS " << fit.rms_px
                << " px): retake it, or use --drop-outliers\n";
    }
  }
  if (floor_removed) {
    std::cerr << "monocle: warning: the floor section of " << written
              << " was made with the old intrinsics and is removed: run monocle floor "
                 "calibrate again\n";
  }
}

// Whether distortion term `i` (k1 k2 p1 p2 k3) is fitted in `model`, or held at 0.
bool DistortionTermFitted(DistortionModel model, int i) {
  if (i < 2) return true;
  if (i < 4) return model != DistortionModel::kK1K2;
  return model == DistortionModel::kK1K2P1P2K3;
}

void PrintText(const IntrinsicCalibration& cal, size_t found, size_t images,
               const std::string& written) {
  const auto& k = cal.intrinsics;
  const auto sigma = cal.Sigma();
  const char* names[] = {"k1", "k2", "p1", "p2", "k3"};
  std::cout << std::fixed << std::setprecision(3) << "images      " << found << " of " << images
            << " with a board\n"
            << "fx fy       " << k.fx << " ± " << sigma[0] << "   " << k.fy << " ± " << sigma[1]
            << " px\n"
            << "cx cy       " << k.cx << " ± " << sigma[2] << "   " << k.cy << " ± " << sigma[3]
            << " px\n"
            << std::setprecision(5);
  for (int i = 0; i < 5; ++i) {
    std::cout << std::setw(12) << std::left << names[i] << std::right << k.distortion[i];
    if (DistortionTermFitted(cal.model, i)) {
      std::cout << " ± " << sigma[4 + i] << "\n";
    } else {
      std::cout << " (fixed: not in the " << ToString(cal.model) << " model)\n";
    }
  }
  const auto map = MapProjectionUncertainty(k, cal.covariance, kProjectionCellPx);
  std::cout << "model       " << cal.model_reason << "\n"
            << "1σ          " << cal.covariance_method << "\n"
            << std::setprecision(2)
            << "projection  1σ of where a ray lands, centre / median / worst: "
            << map.absolute.centre_px << " / " << map.absolute.median_px << " / "
            << map.absolute.worst_px << " px; after the best camera rotation "
            << map.relative.centre_px << " / " << map.relative.median_px << " / "
            << map.relative.worst_px << " px, worst at (" << std::setprecision(0)
            << map.relative.worst_at_px.x() << ", " << map.relative.worst_at_px.y() << ")\n"
            << std::setprecision(4) << "rms         " << cal.rms_px
            << " px (one corner coordinate: 1σ " << cal.corner_sigma_px << " px)\n"
            << std::setprecision(0) << "coverage    " << 100 * cal.coverage
            << " % of the image; largest tilt " << cal.max_tilt_deg << " deg\n";
  std::cout << "views       RMS px   tilt deg\n" << std::setprecision(3);
  for (const auto& fit : cal.views) {
    std::cout << "  " << fit.name << "  " << fit.rms_px << "   " << std::setprecision(0)
              << fit.tilt_deg << std::setprecision(3)
              << (fit.dropped   ? "  outlier, dropped"
                  : fit.outlier ? "  OUTLIER"
                                : "")
              << (fit.rejected_corners
                      ? "  (" + std::to_string(fit.rejected_corners) + " corners left out)"
                      : "")
              << "\n";
  }
  std::cout << "written to  " << written << "\n";
}

// Writes the intrinsics into `path`, keeping the rest of a file already there except its
// floor section, which the old intrinsics made (`floor_removed` says whether there was one).
Status WriteIntrinsics(const std::string& path, const IntrinsicCalibration& cal,
                       bool* floor_removed) {
  CameraCalibration file;
  *floor_removed = false;
  if (auto existing = LoadCalibrationFile(path); existing) {
    file = *existing;
    *floor_removed = file.floor.has_value();
    file.floor.reset();
  }
  file.intrinsics = cal.intrinsics;
  file.intrinsics_rms_px = cal.rms_px;
  file.intrinsics_covariance = cal.covariance;
  file.distortion_model = ToString(cal.model);
  return SaveCalibrationFileAtomically(path, file);
}

}  // namespace

int IntrinsicsCommand(const std::vector<std::string>& argv) {
  IntrinsicsArgs a;
  CommandLine line("intrinsics calibrate", kAbout);
  DeclareIntrinsics(line, &a);
  if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
    std::cout << "Usage: monocle intrinsics calibrate|import|export ...  (monocle intrinsics "
                 "COMMAND --help)\n";
    return argv.empty() ? kExitUsage : kExitOk;
  }
  if (argv[0] == "import") return IntrinsicsImportCommand({argv.begin() + 1, argv.end()});
  if (argv[0] == "export") return IntrinsicsExportCommand({argv.begin() + 1, argv.end()});
  if (argv[0] != "calibrate") {
    return Fail("unknown intrinsics command '" + argv[0] + "' (calibrate, import or export)",
                kExitUsage);
  }
  if (const auto exit_now = line.Parse({argv.begin() + 1, argv.end()})) return *exit_now;
  const auto& paths = a.images;
  const auto& overlay_dir = a.overlay_dir;
  const std::string& out_path = a.out_path;
  const IntrinsicCalibrationOptions& options = a.options;
  if (overlay_dir) {
    std::error_code ec;
    std::filesystem::create_directories(*overlay_dir, ec);
    if (ec)
      return Fail("cannot create --overlay folder '" + *overlay_dir + "': " + ec.message(),
                  kExitFailure);
  }

  proto::IntrinsicsOutput out;
  std::vector<IntrinsicView> views;
  cv::Size size;
  if (int status = DetectBoards(paths, a.board.Spec(), &out, &views, &size); status != kExitOk)
    return status;
  ProgressLine progress("calibrating", 1);
  progress.Message("calibrating from " + std::to_string(views.size()) + " of " +
                   std::to_string(paths.size()) + " images...");
  if (views.size() < 3) {
    progress.Done();
    return Fail("the board was found in only " + std::to_string(views.size()) +
                    " images; at least 3 are needed",
                kExitFailure);
  }
  const auto cal = CalibrateIntrinsics(views, size, options);
  progress.Done();
  if (!cal) return Fail(cal.error(), kExitFailure);
  bool floor_removed = false;
  if (Status saved = WriteIntrinsics(out_path, *cal, &floor_removed); !saved)
    return Fail(saved.error(), kExitFailure);
  if (overlay_dir) {
    if (Status w = WriteOverlays(*overlay_dir, views, *cal, size); !w)
      return Fail(w.error(), kExitFailure);
  }
  if (a.corners_path) {
    if (Status w = WriteMrcalCorners(*a.corners_path, views, *cal); !w)
      return Fail(w.error(), kExitFailure);
  }
  FillOutput(*cal, out_path, floor_removed, &out);
  PrintWarnings(*cal, out_path, floor_removed);
  if (a.json) {
    std::cout << ToJson(out) << "\n";
    return kExitOk;
  }
  PrintText(*cal, views.size(), paths.size(), out_path);
  return kExitOk;
}

}  // namespace monocle::cli
