// monocle floor calibrate | measure (offline: image and calibration files).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "client/cli/floor_map.h"
#include "client/cli/floor_overlay.h"
#include "client/cli/live.h"
#include "idl/cli_output.pb.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/point_queries.h"

#include <unistd.h>
#include <chrono>
#include <optional>
#include "service/vision/chessboard.h"
#include "service/vision/floor_calibrator.h"

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

constexpr const char* kCalibrateHelp =
    R"(Usage: monocle floor calibrate IMAGE --calibration CAL.pbtxt --board COLSxROWS --square METRES
                                [--method full|paper] [--target-sigma M[@D]] [--pixel-sigma PX]
                                [--overlay OUT.png] [--write] [--json]
       monocle floor calibrate --camera ID --board COLSxROWS --square METRES [--json]

Finds a chessboard lying on the floor in IMAGE and computes the camera's pose above the
floor: height h (metres, optical centre above the floor), pitch theta (rad, angle between
the floor's up normal and the optical axis), yaw alpha (rad, board x axis against the
robot's X_w, eq. 10 of Xu et al.) and roll (rad, about the optical axis).

  --calibration CAL.pbtxt  calibration file with the camera's intrinsics (required)
  --board COLSxROWS        inner corners of the board, e.g. 9x6 (required)
  --square METRES          side of one square, metres (required)
  --method full|paper      full: all six degrees of freedom by minimising the corners'
                           reprojection error (default); paper: Xu et al. eq. (13) by
                           least squares, then eq. (15); roll is fixed at 0
  --target-sigma M[@D]     the accuracy you need: 1 sigma of a floor point at most M metres,
                           D metres ahead (default 3). Says whether this calibration meets it
                           and, if not, what to change: the board too far, too small in the
                           image or seen too obliquely, with the 1 sigma the change would give
  --pixel-sigma PX         noise of a measured pixel for the accuracy figures, pixels
                           (default 0.5, as floor measure)
  --overlay OUT.png        write a picture: corners found (green), the board reprojected
                           through the result (blue), the horizon (orange), the robot frame's
                           axes X_w (red) and Y_w (magenta), distances ahead (yellow)
  --write                  store the result in CAL.pbtxt (atomically); refused when the
                           result is ill-conditioned
  --json                   print one JSON object: height pitch yaw roll rms_px sigma{...}
                           method corners written board accuracy[] target_* advice[]
                           ill_conditioned explanation overlay

Also printed: where the board lay, the 1 sigma of a floor point 1, 2 and 4 m straight
ahead (and where it comes from: the calibration, its intrinsics, the measured pixel).
A result whose 1 sigma says it carries no information (height > 25 %, pitch > 0.1 rad),
as the paper's linear solve often is for a small board, is explained and exits with 1.

Live, from the running service (monocled) over DDS, instead of IMAGE and --calibration:
  monocle floor calibrate --camera ID --board COLSxROWS --square METRES [--json]
  --camera ID              a floor camera of the service: it calibrates from the camera's
                           next frame, writes its calibration file atomically and publishes
                           the new calibration (topic /monocle/calibrations); a camera
                           that has just started is waited for up to 20 s
  --domain D               DDS domain id (default 0); --timeout S (default 30)
  --security DIR           this client's identity (operator role) of a secured service's
                           keystore (`monocle security init`; default $MONOCLE_SECURITY)

Board axes: x_p to the right in the image, y_p away from the camera.
)";

constexpr const char* kMeasureHelp =
    R"(Usage: monocle floor measure --calibration CAL.pbtxt [--pixel-sigma PX] [--json] POINT...

Measures points in the robot frame (metres): origin on the floor under the optical
centre, X_w along the image's horizontal axis, Y_w forward, Z_w up.

  POINT                   u,v        a pixel on the floor -> (x, y, 0)       (eq. 5)
                          u,v@fu,fv  a pixel standing vertically above the floor
                                     pixel fu,fv -> (x, y, z)                (eq. 7)
  --calibration CAL.pbtxt a calibration file with a floor section (required)
  --pixel-sigma PX        1-sigma noise of each pixel coordinate, pixels (default 0.5)
  --json                  print one JSON array, per point {x, y, z, sigma{x, y, z}} or
                          {error}

Each result's sigma combines the calibration's covariance and the pixel noise.

Live, from the running service (monocled) over DDS, instead of --calibration:
  --camera ID             the floor camera monocled answers for (e.g. sim-floor)
  --domain D              DDS domain id (default 0); --timeout S (default 10)
  --security DIR          this client's identity of a secured service's keystore
                          (`monocle security init`; default $MONOCLE_SECURITY)
Exit status 1 when any point could not be measured.
)";

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

// The service calibrates its camera from the camera's next frame, stores and publishes it.
int CalibrateLive(const Args& args, const BoardSpec& spec) {
  for (const char* offline :
       {"--calibration", "--method", "--write", "--overlay", "--target-sigma", "--pixel-sigma"}) {
    if (args.Has(offline) || args.Get(offline))
      return Fail(std::string(offline) +
                      " is for images; with --camera the service calibrates "
                      "with the full method and stores the result in its own calibration file",
                  kExitUsage);
  }
  if (!args.positionals().empty())
    return Fail("with --camera no IMAGE is given: the camera's next frame is used", kExitUsage);
  int status = kExitOk;
  // A camera that has just started may take the service up to 20 s to deliver a first frame.
  auto client = OpenClient(args, &status, 30);
  if (!client) return status;
  const std::string camera = *args.Get("--camera");
  const auto r = client->calibrate_floor(camera, spec.cols, spec.rows, spec.square_m);
  if (!r) return Fail(r.error());
  proto::FloorCalibrationOutput out;
  out.set_height(r->floor.height_m);
  out.set_pitch(r->floor.pitch_rad);
  out.set_yaw(r->floor.yaw_rad);
  out.set_roll(r->floor.roll_rad);
  out.set_rms_px(r->floor.rms_px);
  out.set_method("full");
  out.set_corners(r->corners);
  out.set_written(r->file);
  out.set_camera(camera);
  out.set_sequence(r->frame_sequence);
  out.set_revision(r->revision);
  out.mutable_sigma()->set_height(r->floor.sigma[0]);
  out.mutable_sigma()->set_pitch(r->floor.sigma[1]);
  out.mutable_sigma()->set_yaw(r->floor.sigma[2]);
  out.mutable_sigma()->set_roll(r->floor.sigma[3]);
  PrintFloorCalibration(out, args.Has("--json"));
  return kExitOk;
}

int Calibrate(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kCalibrateHelp;
    return kExitOk;
  }
  auto args = Args::Parse(
      argv, {{"--calibration", "--board", "--square", "--method", "--camera", "--domain",
              "--timeout", "--security", "--overlay", "--target-sigma", "--pixel-sigma"},
             {"--write", "--json"}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto spec = RequireBoard(*args);
  if (!spec) return Fail(spec.error(), kExitUsage);
  if (args->Get("--camera")) return CalibrateLive(*args, *spec);
  if (args->positionals().size() != 1)
    return Fail("floor calibrate takes exactly one IMAGE, or --camera ID (see --help)", kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const std::string method_text = args->Get("--method").value_or("full");
  if (method_text != "full" && method_text != "paper") {
    return Fail("--method must be full or paper, not '" + method_text + "'", kExitUsage);
  }
  const auto method =
      method_text == "paper" ? FloorCalibrationMethod::kPaper : FloorCalibrationMethod::kFull;
  std::optional<FloorAccuracyTarget> target;
  if (const auto text = args->Get("--target-sigma")) {
    auto parsed = ParseTarget(*text);
    if (!parsed) return Fail(parsed.error(), kExitUsage);
    target = *parsed;
  }
  const auto pixel_sigma = args->GetDouble("--pixel-sigma", kDefaultPixelSigmaPx);
  if (!pixel_sigma || *pixel_sigma < 0)
    return Fail("--pixel-sigma must be a number of pixels >= 0", kExitUsage);

  auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  const auto image = ReadGreyImage(args->positionals()[0]);
  if (!image) return Fail(image.error(), kExitFailure);
  const auto calibrated = CalibrateFloorFromImage(*image, calibration->intrinsics, *spec, method,
                                                  calibration->intrinsics_covariance);
  if (!calibrated) return Fail(calibrated.error(), kExitFailure);
  const FloorCalibration* result = &calibrated->calibration;
  const size_t corners = calibrated->corners;
  const FloorGuidance guidance =
      AdviseFloorCalibration(calibration->intrinsics, calibration->intrinsics_covariance, *result,
                             calibrated->board, *pixel_sigma, target);

  std::string overlay;
  if (const auto path = args->Get("--overlay")) {
    const auto w = WriteImage(*path, DrawFloorOverlay(*image, calibration->intrinsics, *result,
                                                      calibrated->board, guidance));
    if (!w) return Fail(w.error(), kExitFailure);
    overlay = *path;
  }
  std::string written;
  if (args->Has("--write") && !guidance.ill_conditioned) {
    CameraCalibration updated = *calibration;
    updated.floor = *result;
    const auto saved = SaveCalibrationFileAtomically(*cal_path, updated);
    if (!saved) return Fail(saved.error(), kExitFailure);
    written = *cal_path;
  }
  proto::FloorCalibrationOutput out;
  out.set_height(result->pose.height_m);
  out.set_pitch(result->pose.pitch_rad);
  out.set_yaw(result->pose.yaw_rad);
  out.set_roll(result->pose.roll_rad);
  out.set_rms_px(result->rms_px);
  out.set_method(ToString(method));
  out.set_corners(static_cast<uint32_t>(corners));
  out.set_written(written);
  const auto sigma = result->Sigma();
  out.mutable_sigma()->set_height(sigma[0]);
  out.mutable_sigma()->set_pitch(sigma[1]);
  out.mutable_sigma()->set_yaw(sigma[2]);
  out.mutable_sigma()->set_roll(sigma[3]);
  out.set_overlay(overlay);
  AddGuidance(guidance, &out);
  PrintFloorCalibration(out, args->Has("--json"));
  if (guidance.ill_conditioned) {
    return Fail(std::string("no usable floor calibration") +
                    (args->Has("--write") ? "; " + *cal_path + " left unchanged" : "") +
                    " (ill-conditioned, see above)",
                kExitFailure);
  }
  return kExitOk;
}

// Prints one result per point, in order; exit status 1 if any failed.
int PrintPoints(const std::vector<std::string>& texts, const RequestAnswer& answer, bool json) {
  bool any_failed = false;
  if (json) std::cout << "[";
  for (size_t i = 0; i < answer.points.size(); ++i) {
    const auto& a = answer.points[i];
    const bool ok = a.status == PointStatus::kMeasured;
    any_failed |= !ok;
    const auto sigma = a.measurement.Sigma();
    const auto& p = a.measurement.p_robot_m;
    if (json) {
      proto::PointOutput out;
      if (ok) {
        out.set_x(p.x());
        out.set_y(p.y());
        out.set_z(p.z());
        out.mutable_sigma()->set_x(sigma.x());
        out.mutable_sigma()->set_y(sigma.y());
        out.mutable_sigma()->set_z(sigma.z());
      } else {
        out.set_error(a.error);
      }
      std::cout << (i ? "," : "") << ToJson(out);
    } else if (ok) {
      std::cout << std::fixed << std::setprecision(4) << texts[i] << "  x=" << p.x()
                << " y=" << p.y() << " z=" << p.z() << " m  (1σ " << sigma.x() << " " << sigma.y()
                << " " << sigma.z() << " m)\n";
    } else {
      std::cout << texts[i] << "  error: " << a.error << "\n";
    }
  }
  if (json) std::cout << "]\n";
  return any_failed ? kExitFailure : kExitOk;
}

int Measure(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kMeasureHelp;
    return kExitOk;
  }
  auto args = Args::Parse(
      argv, {{"--calibration", "--pixel-sigma", "--camera", "--domain", "--timeout", "--security"},
             {"--json"}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto pixel_sigma = args->GetDouble("--pixel-sigma", kDefaultPixelSigmaPx);
  if (!pixel_sigma || *pixel_sigma < 0)
    return Fail("--pixel-sigma must be a number of pixels >= 0", kExitUsage);
  if (args->positionals().empty())
    return Fail("no POINT given (u,v or u,v@fu,fv; see --help)", kExitUsage);
  // Malformed points are a command-line error: reject them all before measuring any.
  std::vector<PixelPair> points;
  for (const auto& text : args->positionals()) {
    const auto p = ParsePointArgument(text);
    if (!p) return Fail(p.error(), kExitUsage);
    points.push_back(p->floor_px
                         ? PixelPair{p->u, p->v, true, p->floor_px->first, p->floor_px->second}
                         : PixelPair{p->u, p->v, false, 0, 0});
  }
  const bool json = args->Has("--json");
  if (const auto camera = args->Get("--camera")) {
    int status = kExitOk;
    auto client = OpenClient(*args, &status);
    if (!client) return status;
    std::vector<PixelQuery> queries;
    for (const auto& p : points) {
      queries.push_back(p.paired ? PixelQuery{p.u, p.v, std::array<double, 2>{p.floor_u, p.floor_v}}
                                 : PixelQuery{p.u, p.v, std::nullopt});
    }
    const auto measured = client->measure(*camera, queries, *pixel_sigma);
    if (!measured) return Fail(measured.error());
    // The service's answer in the offline form, so both print the same way.
    RequestAnswer answer;
    for (const auto& m : *measured) {
      PointAnswer a;
      a.status = static_cast<PointStatus>(m.status);
      a.error = m.error;
      a.measurement.p_robot_m = Eigen::Vector3d(m.p_robot_m[0], m.p_robot_m[1], m.p_robot_m[2]);
      a.measurement.covariance =
          Eigen::Vector3d(m.sigma_m[0], m.sigma_m[1], m.sigma_m[2]).cwiseAbs2().asDiagonal();
      answer.points.push_back(std::move(a));
    }
    return PrintPoints(args->positionals(), answer, json);
  }
  const auto cal_path = args->Require("--calibration");
  if (!cal_path)
    return Fail("missing --calibration CAL.pbtxt (or --camera ID to ask the service)", kExitUsage);
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) {
    return Fail(
        *cal_path + " has no floor section: run 'monocle floor calibrate ... --write' first",
        kExitFailure);
  }
  // The same computation the service runs for a query.
  const auto answer =
      AnswerPointRequest({{*cal_path, *calibration}}, *cal_path, points, *pixel_sigma);
  if (answer.status != RequestStatus::kAnswered) return Fail(answer.error, kExitFailure);
  return PrintPoints(args->positionals(), answer, json);
}

constexpr const char* kProjectHelp =
    R"(Usage: monocle floor project --calibration CAL.pbtxt [--json] X,Y,Z...

The inverse of measure: the pixel (u, v) where the calibrated camera sees each robot-frame
point X,Y,Z (metres; Z up from the floor). Prints "u,v" per point, or --json an array of
{u, v} objects ({error} for a point behind the camera).
)";

int Project(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kProjectHelp;
    return kExitOk;
  }
  auto args = Args::Parse(argv, {{"--calibration"}, {"--json"}});
  if (!args) return Fail(args.error(), kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  if (args->positionals().empty())
    return Fail("no X,Y,Z point given (metres; see --help)", kExitUsage);
  std::vector<Eigen::Vector3d> points;
  for (const auto& text : args->positionals()) {
    const auto v = ParseNumberList(text);
    if (!v || v->size() != 3)
      return Fail("point '" + text + "' is not X,Y,Z in metres", kExitUsage);
    points.emplace_back((*v)[0], (*v)[1], (*v)[2]);
  }
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  if (!calibration->floor) return Fail(*cal_path + " has no floor section", kExitFailure);
  bool any_failed = false;
  const bool json = args->Has("--json");
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
      std::cout << "error: " << args->positionals()[i] << " is behind the camera\n";
    }
  }
  if (json) std::cout << "]\n";
  return any_failed ? kExitFailure : kExitOk;
}

constexpr const char* kMapHelp =
    R"(Usage: monocle floor map --calibration CAL.pbtxt --out MAP.png [--range M]
                         [--resolution M] [--pixel-sigma PX]

The floor seen from above: where the calibrated camera sees the floor (its footprint, white
outline), rings every metre around the robot origin (below the optical centre; X_w right,
Y_w forward = up), and the horizontal 1-sigma of a floor point as colour (log scale, 1 mm
blue to 1 m red) with contours at 5 mm, 1, 2, 5, 10, 20 and 50 cm. Each cell's 1-sigma is what
`floor measure` reports for the pixel that sees it: the calibration's covariance (pose and
intrinsics) and the pixel noise, propagated to first order (Xu et al. 2017, section 4).

  --range M          metres shown ahead and to each side (default 6)
  --resolution M     metres per map pixel (default 0.01)
  --pixel-sigma PX   pixel noise, 1-sigma (default 0.5)
)";

int Map(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kMapHelp;
    return kExitOk;
  }
  auto args = Args::Parse(
      argv, {{"--calibration", "--out", "--range", "--resolution", "--pixel-sigma"}, {}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (!args->positionals().empty())
    return Fail("floor map takes no positional arguments", kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const auto out = args->Require("--out");
  if (!out) return Fail(out.error(), kExitUsage);
  FloorMapOptions options;
  const auto range = args->GetDouble("--range", options.range_m);
  const auto resolution = args->GetDouble("--resolution", options.metres_per_px);
  const auto pixel_sigma = args->GetDouble("--pixel-sigma", options.pixel_sigma_px);
  if (!range) return Fail(range.error(), kExitUsage);
  if (!resolution) return Fail(resolution.error(), kExitUsage);
  if (!pixel_sigma) return Fail(pixel_sigma.error(), kExitUsage);
  options.range_m = *range;
  options.metres_per_px = *resolution;
  options.cell_m = std::max(options.cell_m, options.metres_per_px);
  options.pixel_sigma_px = *pixel_sigma;
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  auto map = RenderFloorMap(*calibration, options);
  if (!map) {
    return Fail(*cal_path + ": " + map.error().message,
                map.error().code == ErrorCode::kInvalidArgument && calibration->floor
                    ? kExitUsage
                    : kExitFailure);
  }
  if (auto w = WriteImage(*out, map->picture); !w) return Fail(w.error(), kExitFailure);
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
