// monocle floor calibrate | measure (offline: image and calibration files).
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "client/cli/args.h"
#include "client/cli/calibration_warnings.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/floor_map.h"
#include "client/cli/live.h"
#include "client/cli/shared_options.h"
#include "idl/cli_output.pb.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/point_queries.h"
#include "service/vision/floor_overlay.h"

#include <unistd.h>
#include <chrono>
#include <optional>
#include "service/vision/chessboard.h"
#include "service/vision/floor_calibrator.h"

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

void PrintFloorCalibration(const proto::FloorCalibrationOutput& out, bool json) {
  if (json) {
    std::cout << ToJson(out) << "\n";
    return;
  }
  const auto& sigma = out.sigma();
  // An ill-conditioned result's sigma is no error bar: say so instead of printing +- 10 m.
  const std::string spread = out.ill_conditioned() ? "  not determined, 1 sigma " : "  ± ";
  std::cout << std::fixed << std::setprecision(6) << "method  " << out.method() << " ("
            << out.corners() << " corners)\n"
            << "height  " << out.height() << " m" << spread << sigma.height() << " m\n"
            << "pitch   " << out.pitch() << " rad" << spread << sigma.pitch() << " rad  ("
            << std::setprecision(4) << out.pitch() * kDeg << "°)\n"
            << std::setprecision(6) << "yaw     " << out.yaw() << " rad" << spread << sigma.yaw()
            << " rad  (" << std::setprecision(4) << out.yaw() * kDeg << "°)\n"
            << std::setprecision(6) << "roll    " << out.roll() << " rad" << spread << sigma.roll()
            << " rad  (" << std::setprecision(4) << out.roll() * kDeg << "°)\n"
            << std::setprecision(4) << "rms     " << out.rms_px() << " px\n";
  if (!out.camera().empty()) {
    std::cout << "camera  " << out.camera() << ", frame " << out.sequence() << ", revision "
              << out.revision() << "\n";
  }
  if (out.has_board()) {
    const auto& b = out.board();
    std::cout << std::setprecision(2) << "board   " << b.distance() << " m away, " << b.depth_span()
              << " m deep, " << std::setprecision(1) << 100 * b.image_fraction()
              << " % of the image, seen " << std::setprecision(0) << b.sight_angle()
              << " deg above the floor\n";
  }
  if (out.ill_conditioned()) std::cout << "ill-conditioned: " << out.explanation() << "\n";
  if (out.accuracy_size() > 0) {
    std::cout
        << "accuracy of a floor point straight ahead, 1 sigma along its least certain direction:\n";
    for (const auto& a : out.accuracy()) {
      std::cout << std::setprecision(1) << "  " << std::setw(5) << a.distance() << " m  "
                << std::setw(7) << a.sigma() * 1e3 << " mm   calibration " << a.calibration() * 1e3
                << " mm (intrinsics " << a.intrinsics() * 1e3 << "), pixel " << a.pixel() * 1e3
                << " mm" << (a.in_image() ? "" : "   (outside the image)") << "\n";
    }
  }
  if (out.has_target_met()) {
    std::cout << std::setprecision(1) << "target  1 sigma <= " << out.target_sigma() * 1e3
              << " mm at " << out.target_distance()
              << " m: " << (out.target_met() ? "met" : "NOT met") << std::setprecision(2);
    if (out.target_met_out_to() > 0)
      std::cout << " (met out to " << out.target_met_out_to() << " m)\n";
    else
      std::cout << " (met nowhere in the image)\n";
  }
  for (const auto& a : out.advice()) std::cout << "advice  " << a << "\n";
  if (!out.overlay().empty()) std::cout << "overlay " << out.overlay() << "\n";
  if (!out.written().empty()) std::cout << "written to " << out.written() << "\n";
}

// "M" or "M@D": 1 sigma M metres at D metres ahead.
Result<FloorAccuracyTarget> ParseTarget(const std::string& text) {
  const auto at = text.find('@');
  const auto sigma = ParseNumberList(text.substr(0, at));
  const auto distance = at == std::string::npos
                            ? std::optional<std::vector<double>>(std::vector<double>{3.0})
                            : ParseNumberList(text.substr(at + 1));
  if (!sigma || sigma->size() != 1 || !((*sigma)[0] > 0) || !distance || distance->size() != 1 ||
      !((*distance)[0] > 0)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--target-sigma '" + text +
                         "' is not M or M@D (metres > 0, e.g. 0.01@4: 1 cm at 4 m ahead)");
  }
  return FloorAccuracyTarget{(*sigma)[0], (*distance)[0]};
}

void AddGuidance(const FloorGuidance& g, proto::FloorCalibrationOutput* out) {
  out->set_ill_conditioned(g.ill_conditioned);
  out->set_explanation(g.ill_conditioned_reason);
  auto* b = out->mutable_board();
  b->set_distance(g.board.distance_m);
  b->set_depth_span(g.board.depth_span_m);
  b->set_image_fraction(g.board.image_fraction);
  b->set_sight_angle(g.board.sight_angle_deg);
  for (const auto& a : g.accuracy) {
    auto* o = out->add_accuracy();
    o->set_distance(a.distance_m);
    o->set_in_image(a.in_image);
    o->set_sigma(a.sigma_m);
    o->set_calibration(a.calibration_sigma_m);
    o->set_intrinsics(a.intrinsics_sigma_m);
    o->set_pixel(a.pixel_sigma_m);
  }
  if (g.target && !g.ill_conditioned) {
    out->set_target_sigma(g.target->sigma_m);
    out->set_target_distance(g.target->distance_m);
    out->set_target_met(g.target_met);
    out->set_target_met_out_to(g.target_met_out_to_m);
  }
  for (const auto& a : g.advice) out->add_advice(a);
}

struct CalibrateArgs {
  std::vector<std::string> image;
  std::string calibration_path;
  BoardOptions board;
  std::string method = "full";
  std::optional<FloorAccuracyTarget> target;
  double pixel_sigma_px = kDefaultPixelSigmaPx;
  std::optional<std::string> overlay;
  bool write = false;
  bool force = false;
  bool json = false;
  LiveOptions live;
};

void DeclareCalibrate(CommandLine& line, CalibrateArgs* a) {
  line.Footer(
      "Also printed: where the board lay, the 1 sigma of a floor point 1, 2 and 4 m straight\n"
      "ahead (and where it comes from: the calibration, its intrinsics, the measured pixel).\n"
      "A result whose 1 sigma says it carries no information (height > 25 %, pitch > 0.1 rad),\n"
      "as the paper's linear solve often is for a small board, is explained and exits with 1.\n\n"
      "Board axes: x_p to the right in the image, y_p away from the camera.");
  DeclareBoard(line, &a->board);
  line.Flag("--json", &a->json,
            "print one JSON object: height pitch yaw roll rms_px sigma{...} method corners "
            "written board accuracy[] target_* advice[] ill_conditioned explanation overlay");
  line.Custom("--target-sigma", "M[@D]",
              "the accuracy you need: 1 sigma of a floor point at most M metres, D metres ahead "
              "(default 3). Says whether this calibration meets it and, if not, what to change: "
              "the board too far, too small in the image or seen too obliquely, with the 1 sigma "
              "the change would give",
              [a](const std::string& text) -> std::optional<std::string> {
                auto target = ParseTarget(text);
                if (!target) return target.error().message;
                a->target = *target;
                return std::nullopt;
              });
  line.Number("--pixel-sigma", &a->pixel_sigma_px, "PX",
              "noise of a measured pixel for the accuracy figures, as floor measure",
              In("pixels").AtLeast(0));
  line.Text("--overlay", &a->overlay, "OUT.png",
            "write a picture (live: sent by the service, written here): corners found (green), the "
            "board reprojected through the result "
            "(blue), the horizon (orange), the robot frame's axes X_w (red) and Y_w (magenta), "
            "distances ahead (yellow)");
  line.Flag("--force", &a->force,
            "keep a result whose height is no robot's (outside 0.05-10 m), which is refused "
            "otherwise as the likely sign of --square in the wrong unit");
  line.InForms({0});
  line.Positionals("IMAGE", &a->image, "a picture of the chessboard lying on the floor", 1, 1);
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "calibration file with the camera's intrinsics");
  line.Require("--calibration");
  line.Choice("--method", &a->method, {"full", "paper"},
              "full: all six degrees of freedom by minimising the corners' reprojection error; "
              "paper: Xu et al. eq. (13) by least squares, then eq. (15); roll is fixed at 0");
  line.Flag("--write", &a->write,
            "store the result in CAL.pbtxt (atomically); refused when the result is "
            "ill-conditioned");
  line.Form(
      "Live, from the running service (monocled) over DDS, instead of IMAGE and "
      "--calibration");
  line.Text("--camera", &a->live.camera, "ID",
            "a floor camera of the service: it calibrates from the camera's next frame, reports "
            "as above, writes its calibration file atomically and publishes the new "
            "calibration (topic /monocle/calibrations); an ill-conditioned result, or one whose "
            "height is no robot's (without --force), is not stored. A camera that has just "
            "started is waited for up to 20 s");
  line.Require("--camera");
  // A camera that has just started may take the service up to 20 s to deliver a first frame.
  a->live.timeout_s = 30;
  DeclareServiceOptions(line, &a->live, "give up after S seconds");
}

// The result and its report as printed, offline or live.
proto::FloorCalibrationOutput ToOutput(const FloorPoseEstimate& floor, const std::string& method,
                                       uint32_t corners, const FloorGuidance& report) {
  proto::FloorCalibrationOutput out;
  out.set_height(floor.height_m);
  out.set_pitch(floor.pitch_rad);
  out.set_yaw(floor.yaw_rad);
  out.set_roll(floor.roll_rad);
  out.set_rms_px(floor.rms_px);
  out.set_method(method);
  out.set_corners(corners);
  out.mutable_sigma()->set_height(floor.sigma[0]);
  out.mutable_sigma()->set_pitch(floor.sigma[1]);
  out.mutable_sigma()->set_yaw(floor.sigma[2]);
  out.mutable_sigma()->set_roll(floor.sigma[3]);
  AddGuidance(report, &out);
  return out;
}

Status WriteBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  if (!file.flush()) return MakeError(ErrorCode::kIo, "cannot write " + path);
  return Ok{};
}

// The service calibrates its camera from the camera's next frame, reports, stores and
// publishes it; the picture it sends is written here.

int CalibrateLive(const CalibrateArgs& a) {
  int status = kExitOk;
  auto client = OpenClient(a.live, &status);
  if (!client) return status;
  const std::string& camera = *a.live.camera;
  const BoardSpec spec = a.board.Spec();
  FloorCalibrationOptions options;
  options.pixel_sigma_px = a.pixel_sigma_px;
  options.target = a.target;
  options.force = a.force;
  options.overlay = a.overlay.has_value();
  const auto r = client->calibrate_floor(camera, spec.cols, spec.rows, spec.square_m, options);
  if (!r) return Fail(r.error());
  FloorGuidance report = r->report;
  report.target = a.target;  // the verdict came back; the target is the one asked for
  proto::FloorCalibrationOutput out = ToOutput(r->floor, "full", r->corners, report);
  if (a.overlay) {
    if (r->overlay_png.empty()) return Fail("monocled sent no picture for --overlay", kExitFailure);
    if (const auto w = WriteBytes(*a.overlay, r->overlay_png); !w)
      return Fail(w.error(), kExitFailure);
    out.set_overlay(*a.overlay);
  }
  out.set_written(r->file);
  out.set_camera(camera);
  out.set_sequence(r->frame_sequence);
  out.set_revision(r->revision);
  out.set_sigma_excludes_intrinsics(WarnIfLiveIntrinsicsHaveNoCovariance(*client, camera));
  PrintFloorCalibration(out, a.json);
  return kExitOk;
}

int Calibrate(const std::vector<std::string>& argv) {
  CalibrateArgs a;
  CommandLine line(
      "floor calibrate",
      "Finds a chessboard lying on the floor in IMAGE and computes the camera's pose above the\n"
      "floor: height h (metres, optical centre above the floor), pitch theta (rad, angle between\n"
      "the floor's up normal and the optical axis), yaw alpha (rad, board x axis against the\n"
      "robot's X_w, eq. 10 of Xu et al.) and roll (rad, about the optical axis).");
  DeclareCalibrate(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  if (a.live.camera) return CalibrateLive(a);
  const auto method =
      a.method == "paper" ? FloorCalibrationMethod::kPaper : FloorCalibrationMethod::kFull;
  const std::string& cal_path = a.calibration_path;
  auto calibration = LoadCalibrationFile(cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  const auto image = ReadGreyImage(a.image[0]);
  if (!image) return Fail(image.error(), kExitFailure);
  const auto calibrated = CalibrateFloorFromImage(*image, calibration->intrinsics, a.board.Spec(),
                                                  method, calibration->intrinsics_covariance);
  if (!calibrated) return Fail(calibrated.error(), kExitFailure);
  const FloorCalibration* result = &calibrated->calibration;
  const size_t corners = calibrated->corners;
  const FloorGuidance guidance =
      AdviseFloorCalibration(calibration->intrinsics, calibration->intrinsics_covariance, *result,
                             calibrated->board, a.pixel_sigma_px, a.target);
  // An ill-conditioned result's height means nothing; a determined one can be judged.
  if (const auto slip = FloorHeightUnitSlip(result->pose.height_m, a.board.square_m);
      slip && !guidance.ill_conditioned && !a.force)
    return Fail(*slip, kExitFailure);

  std::string overlay;
  if (a.overlay) {
    const auto w = WriteImage(*a.overlay, DrawFloorOverlay(*image, calibration->intrinsics, *result,
                                                           calibrated->board, guidance));
    if (!w) return Fail(w.error(), kExitFailure);
    overlay = *a.overlay;
  }
  std::string written;
  if (a.write && !guidance.ill_conditioned) {
    CameraCalibration updated = *calibration;
    updated.floor = *result;
    const auto saved = SaveCalibrationFileAtomically(cal_path, updated);
    if (!saved) return Fail(saved.error(), kExitFailure);
    written = cal_path;
  }
  const auto sigma = result->Sigma();
  const FloorPoseEstimate estimate{result->pose.height_m,
                                   result->pose.pitch_rad,
                                   result->pose.yaw_rad,
                                   result->pose.roll_rad,
                                   {sigma[0], sigma[1], sigma[2], sigma[3]},
                                   result->rms_px};
  proto::FloorCalibrationOutput out =
      ToOutput(estimate, ToString(method), static_cast<uint32_t>(corners), guidance);
  out.set_written(written);
  out.set_overlay(overlay);
  out.set_sigma_excludes_intrinsics(WarnIfIntrinsicsHaveNoCovariance(cal_path, *calibration));
  PrintFloorCalibration(out, a.json);
  if (guidance.ill_conditioned) {
    return Fail(std::string("no usable floor calibration") +
                    (a.write ? "; " + cal_path + " left unchanged" : "") +
                    " (ill-conditioned, see above)",
                kExitFailure);
  }
  return kExitOk;
}

// Prints one result per point, in order; exit status 1 if any failed.
int PrintPoints(const std::vector<std::string>& texts, const std::vector<MeasuredPoint>& points,
                bool json, bool sigma_excludes_intrinsics = false) {
  bool any_failed = false;
  if (json) std::cout << "[";
  for (size_t i = 0; i < points.size(); ++i) {
    const MeasuredPoint& a = points[i];
    any_failed |= !a.ok();
    const auto& sigma = a.sigma_m;
    const auto& p = a.p_robot_m;
    if (json) {
      proto::PointOutput out;
      if (a.ok()) {
        out.set_x(p[0]);
        out.set_y(p[1]);
        out.set_z(p[2]);
        out.mutable_sigma()->set_x(sigma[0]);
        out.mutable_sigma()->set_y(sigma[1]);
        out.mutable_sigma()->set_z(sigma[2]);
        for (double c : a.covariance) out.add_covariance(c);
        out.set_sigma_excludes_intrinsics(sigma_excludes_intrinsics);
      } else {
        out.set_error(a.error);
      }
      std::cout << (i ? "," : "") << ToJson(out);
    } else if (a.ok()) {
      std::cout << std::fixed << std::setprecision(4) << texts[i] << "  x=" << p[0] << " y=" << p[1]
                << " z=" << p[2] << " m  (1σ " << sigma[0] << " " << sigma[1] << " " << sigma[2]
                << " m)\n";
    } else {
      std::cout << texts[i] << "  error: " << a.error << "\n";
    }
  }
  if (json) std::cout << "]\n";
  return any_failed ? kExitFailure : kExitOk;
}

struct MeasureArgs {
  std::vector<std::string> points;
  std::string calibration_path;
  double pixel_sigma_px = kDefaultPixelSigmaPx;
  bool json = false;
  LiveOptions live;
};

void DeclareMeasure(CommandLine& line, MeasureArgs* a) {
  line.Positionals("POINT", &a->points,
                   "u,v: a pixel on the floor -> (x, y, 0) (eq. 5); u,v@fu,fv: a pixel standing "
                   "vertically above its foot, the floor pixel fu,fv -> (x, y, z) (eq. 7)");
  line.Number("--pixel-sigma", &a->pixel_sigma_px, "PX", "1-sigma noise of each pixel coordinate",
              In("pixels").AtLeast(0));
  line.Flag("--json", &a->json,
            "print one JSON array, per point {x, y, z, sigma{x, y, z}, covariance[9]} or {error}; "
            "covariance is row-major 3x3 of (x, y, z), square metres");
  line.InForms({0});
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "a calibration file with a floor section");
  line.Require("--calibration");
  line.Form("Live, from the running service (monocled) over DDS, instead of --calibration");
  line.Text("--camera", &a->live.camera, "ID",
            "the floor camera monocled answers for (e.g. "
            "sim-floor)");
  line.Require("--camera");
  DeclareServiceOptions(line, &a->live, "give up after S seconds");
  line.Footer(
      "Each result's sigma combines the calibration's covariance and the pixel noise.\n"
      "Exit status 1 when any point could not be measured.");
}

int Measure(const std::vector<std::string>& argv) {
  MeasureArgs a;
  CommandLine line("floor measure",
                   "Measures points in the robot frame (metres): origin on the floor under the "
                   "optical\ncentre, X_w along the image's horizontal axis, Y_w forward, Z_w up.");
  DeclareMeasure(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  // Malformed points are a command-line error: reject them all before measuring any.
  std::vector<PixelQuery> points;
  for (const auto& text : a.points) {
    const auto p = ParsePointArgument(text);
    if (!p) return Fail(p.error(), kExitUsage);
    points.push_back(*p);
  }
  if (a.live.camera) {
    int status = kExitOk;
    auto client = OpenClient(a.live, &status);
    if (!client) return status;
    const auto measured = client->measure(*a.live.camera, points, a.pixel_sigma_px);
    if (!measured) return Fail(measured.error());
    const bool excludes = WarnIfLiveIntrinsicsHaveNoCovariance(*client, *a.live.camera);
    return PrintPoints(a.points, *measured, a.json, excludes);
  }
  const std::string& cal_path = a.calibration_path;
  const auto calibration = LoadCalibrationFile(cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) {
    return Fail(cal_path + " has no floor section: run 'monocle floor calibrate ... --write' first",
                kExitFailure);
  }
  // The same computation the service runs for a query.
  const auto answer =
      AnswerPointRequest({{cal_path, *calibration}}, cal_path, points, a.pixel_sigma_px);
  if (answer.status != RequestStatus::kAnswered) return Fail(answer.error, kExitFailure);
  const bool excludes = WarnIfIntrinsicsHaveNoCovariance(cal_path, *calibration);
  return PrintPoints(a.points, answer.points, a.json, excludes);
}

int Project(const std::vector<std::string>& argv) {
  std::vector<std::string> texts;
  std::string cal_path;
  bool json = false;
  CommandLine line("floor project",
                   "The inverse of measure: the pixel (u, v) where the calibrated camera sees each "
                   "robot-frame\npoint X,Y,Z (metres; Z up from the floor). Prints \"u,v\" per "
                   "point, or --json an array of\n{u, v} objects ({error} for a point behind the "
                   "camera).");
  line.Positionals("X,Y,Z", &texts, "a point in the robot frame, metres");
  line.Text("--calibration", &cal_path, "CAL.pbtxt", "a calibration file with a floor section");
  line.Require("--calibration");
  line.Flag("--json", &json, "print one JSON array of {u, v} or {error}");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  std::vector<Eigen::Vector3d> points;
  for (const auto& text : texts) {
    const auto v = ParseNumberList(text);
    if (!v || v->size() != 3)
      return Fail("point '" + text + "' is not X,Y,Z in metres", kExitUsage);
    points.emplace_back((*v)[0], (*v)[1], (*v)[2]);
  }
  const auto calibration = LoadCalibrationFile(cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) return Fail(cal_path + " has no floor section", kExitFailure);
  bool any_failed = false;
  if (json) std::cout << "[";
  for (size_t i = 0; i < points.size(); ++i) {
    const auto px = ProjectRobotPoint(calibration->intrinsics, calibration->floor->pose, points[i]);
    any_failed |= !px.has_value();
    std::ostringstream os;
    os << std::setprecision(10);
    if (json) {
      if (px) {
        os << "{\"u\":" << px->x() << ",\"v\":" << px->y() << "}";
      } else {
        os << "{\"error\":\"point is behind the camera\"}";
      }
      std::cout << (i ? "," : "") << os.str();
    } else if (px) {
      os << std::fixed << std::setprecision(3) << px->x() << "," << px->y();
      std::cout << os.str() << "\n";
    } else {
      std::cout << "error: " << texts[i] << " is behind the camera\n";
    }
  }
  if (json) std::cout << "]\n";
  return any_failed ? kExitFailure : kExitOk;
}

int Map(const std::vector<std::string>& argv) {
  std::string cal_path, out;
  FloorMapOptions options;
  CommandLine line(
      "floor map",
      "The floor seen from above: where the calibrated camera sees the floor (its footprint, "
      "white\noutline), rings every metre around the robot origin (below the optical centre; X_w "
      "right,\nY_w forward = up), and the horizontal 1-sigma of a floor point as colour (log "
      "scale, 1 mm\nblue to 1 m red) with contours at 5 mm, 1, 2, 5, 10, 20 and 50 cm. Each "
      "cell's 1-sigma is what\n`floor measure` reports for the pixel that sees it: the "
      "calibration's covariance (pose and\nintrinsics) and the pixel noise, propagated to first "
      "order (Xu et al. 2017, section 4).");
  line.Text("--calibration", &cal_path, "CAL.pbtxt", "a calibration file with a floor section");
  line.Require("--calibration");
  line.Text("--out", &out, "MAP.png", "the picture to write");
  line.Require("--out");
  line.Number("--range", &options.range_m, "M", "shown ahead and to each side",
              In("metres").Above(0));
  line.Number("--resolution", &options.metres_per_px, "M", "per map pixel", In("metres").Above(0));
  line.Number("--pixel-sigma", &options.pixel_sigma_px, "PX", "pixel noise, 1 sigma",
              In("pixels").AtLeast(0));
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  options.cell_m = std::max(options.cell_m, options.metres_per_px);
  const auto calibration = LoadCalibrationFile(cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  auto map = RenderFloorMap(*calibration, options);
  if (!map) {
    return Fail(cal_path + ": " + map.error().message,
                map.error().code == ErrorCode::kInvalidArgument && calibration->floor
                    ? kExitUsage
                    : kExitFailure);
  }
  if (auto w = WriteImage(out, map->picture); !w) return Fail(w.error(), kExitFailure);
  return kExitOk;
}

}  // namespace

int FloorCommand(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << "Usage: monocle floor calibrate|measure|project|map ...  (monocle floor COMMAND "
                 "--help)\n";
    return args.empty() ? kExitUsage : kExitOk;
  }
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "calibrate") return Calibrate(rest);
  if (args[0] == "measure") return Measure(rest);
  if (args[0] == "project") return Project(rest);
  if (args[0] == "map") return Map(rest);
  return Fail("unknown floor command '" + args[0] + "' (calibrate, measure, project or map)",
              kExitUsage);
}

}  // namespace monocle::cli
