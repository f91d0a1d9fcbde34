// monocle corner locate (offline: images and a calibration file).
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "client/cli/live.h"
#include "idl/cli_output.pb.h"
#include "service/io/calibration_file.h"
#include "service/vision/corner_locator.h"
#include "service/vision/corner_tracker.h"

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

constexpr const char* kLocateHelp =
    R"(Usage: monocle corner locate IMAGE... --calibration CAL.pbtxt [--ceiling-distance Z]
                             [--json] [--overlay DIR] [--track [--detect-every N]]

Finds the ceiling corner (two ceiling edges and the vertical wall edge meeting in a Y) in
each image and computes the camera's pose in the corner frame (Chou & Tsai 1986): origin
at the corner, X and Y along the ceiling edges, Z down the vertical edge, room at x, y,
z > 0. Position x, y, z in metres (z = the camera-to-ceiling distance), pan, tilt, swing in
radians as the paper's eq. (1) (tilt 0 looks straight up, swing 0 is an upright camera).

  --calibration CAL.pbtxt  intrinsics (pixels are undistorted first) and optionally
                           corner { ceiling_distance }
  --ceiling-distance Z     camera optical centre to ceiling, metres (overrides the file)
  --json                   one JSON object per line: image x y z pan tilt swing
                           quaternion corner_px rms_px sigma lines (with each edge's
                           support) source suspect [suspect_reason] noise_grey, or image
                           error
  --overlay DIR            write DIR/<image>.overlay.png with the edges, corner and pose
  --track                  the images are an ordered sequence (frames of a video): predict
                           the three edges from the previous pose and measure them there
                           first; a full detection when that fails, when the tracked pose is
                           suspect, and every --detect-every N images (default 30). Each
                           result says "tracked" or "detected".

Every pose says how well the image supports it: per edge the length found, its contrast
against the image's noise, and how far its points lie from the pose's line. A pose whose
edges disagree, or that is weakly determined (1 sigma above 2 % of the distance), is
printed as SUSPECT with the reason; it is never dropped silently.

Live, from the running service (monocled) over DDS, instead of IMAGE files:
  --camera ID              the camera's poses as monocled publishes them (same JSON as
                           above, inside {camera, sequence, capture_time_ns, time_source,
                           pose})
  --count N                stop after N poses (default 1); --follow: until Ctrl-C
  --domain D               DDS domain id (default 0); --timeout S: give up after S seconds
                           without a pose (default 10)
  --security DIR           this client's identity of a secured service's keystore
                           (`monocle security init`; default $MONOCLE_SECURITY)

Any image OpenCV reads (PNG, PGM, JPEG, ...). An image without a corner is reported and
the others are still processed; the exit status is 1 if any image failed.
)";

const char* kAxisName[3] = {"X", "Y", "Z"};

void WriteOverlay(const std::string& dir, const std::string& image_path, const cv::Mat& grey,
                  const Result<CornerLocation>& result) {
  cv::Mat color;
  cv::cvtColor(grey, color, cv::COLOR_GRAY2BGR);
  auto pt = [](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
  };
  std::string text;
  if (result) {
    for (const auto& s : result->edges.hough_segments)
      cv::line(color, pt(s.a_px), pt(s.b_px), cv::Scalar(0, 200, 255), 1, cv::LINE_AA);
    const cv::Scalar colors[3] = {cv::Scalar(0, 0, 255), cv::Scalar(0, 200, 0),
                                  cv::Scalar(255, 0, 0)};
    for (int a = 0; a < 3; ++a) {
      cv::line(color, pt(result->corner_px), pt(result->line_end_px[a]), colors[a], 2, cv::LINE_AA);
      cv::putText(color, kAxisName[a],
                  pt(result->line_end_px[a] + 0.1 * (result->corner_px - result->line_end_px[a])),
                  cv::FONT_HERSHEY_SIMPLEX, 1.0, colors[a], 2);
    }
    cv::circle(color, pt(result->corner_px), 8, cv::Scalar(0, 255, 255), 2, cv::LINE_AA);
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << "x " << result->pose.x_m << " y "
       << result->pose.y_m << " z " << result->pose.z_m << " m  pan " << std::setprecision(2)
       << result->pose.pan_rad * kDeg << " tilt " << result->pose.tilt_rad * kDeg << " swing "
       << result->pose.swing_rad * kDeg << " deg";
    text = os.str();
  } else {
    text = result.error().message;
  }
  cv::putText(color, text, cv::Point(12, 32), cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(0, 0, 0),
              4);
  cv::putText(color, text, cv::Point(12, 32), cv::FONT_HERSHEY_SIMPLEX, 0.8,
              cv::Scalar(0, 255, 255), 2);
  if (result) {
    // Second line: where the pose came from and how well each edge supports it.
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << ToString(result->source) << "  noise "
       << result->noise_sigma_grey << " grey";
    for (int a = 0; a < 3; ++a) {
      const auto& s = result->support[a];
      os << "  " << kAxisName[a] << ": " << std::setprecision(0) << s.length_px << " px, "
         << std::setprecision(1) << s.contrast_to_noise << "x noise";
    }
    cv::putText(color, os.str(), cv::Point(12, 64), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 0, 0), 4);
    cv::putText(color, os.str(), cv::Point(12, 64), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 255, 255), 1);
    if (result->suspect) {
      const std::string warning = "SUSPECT: " + result->suspect_reason;
      cv::putText(color, warning, cv::Point(12, 92), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                  cv::Scalar(0, 0, 0), 4);
      cv::putText(color, warning, cv::Point(12, 92), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                  cv::Scalar(0, 0, 255), 2);
    }
  }
  const std::string out = (std::filesystem::path(dir) /
                           (std::filesystem::path(image_path).stem().string() + ".overlay.png"))
                              .string();
  if (!cv::imwrite(out, color))
    std::cerr << "monocle: warning: cannot write overlay " << out << "\n";
}

proto::CornerOutput ToOutput(const std::string& image, const Result<CornerLocation>& r) {
  proto::CornerOutput out;
  out.set_image(image);
  if (!r) {
    out.set_error(r.error().message);
    return out;
  }
  const auto& p = r->pose;
  out.set_x(p.x_m);
  out.set_y(p.y_m);
  out.set_z(p.z_m);
  out.set_pan(p.pan_rad);
  out.set_tilt(p.tilt_rad);
  out.set_swing(p.swing_rad);
  for (double v : {r->q_corner_camera.w(), r->q_corner_camera.x(), r->q_corner_camera.y(),
                   r->q_corner_camera.z()})
    out.add_quaternion(v);
  out.add_corner_px(r->corner_px.x());
  out.add_corner_px(r->corner_px.y());
  out.set_rms_px(r->rms_px);
  const auto s = r->Sigma();
  out.mutable_sigma()->set_x(s[0]);
  out.mutable_sigma()->set_y(s[1]);
  out.mutable_sigma()->set_pan(s[2]);
  out.mutable_sigma()->set_tilt(s[3]);
  out.mutable_sigma()->set_swing(s[4]);
  for (int a = 0; a < 3; ++a) {
    auto* line = out.add_lines();
    line->set_axis(kAxisName[a]);
    line->add_from_px(r->corner_px.x());
    line->add_from_px(r->corner_px.y());
    line->add_to_px(r->line_end_px[a].x());
    line->add_to_px(r->line_end_px[a].y());
    line->set_points(r->points_per_line[a]);
    const EdgeSupport& s = r->support[a];
    line->set_length_px(s.length_px);
    line->set_visible_length_px(s.visible_length_px);
    line->set_coverage(s.coverage);
    line->set_contrast_grey(s.contrast_grey);
    line->set_contrast_to_noise(s.contrast_to_noise);
    line->set_edge_rms_px(s.rms_px);
    line->set_sigma_px(s.sigma_px);
    line->set_misfit_px(s.misfit_px);
  }
  out.set_source(ToString(r->source));
  out.set_suspect(r->suspect);
  if (r->suspect) out.set_suspect_reason(r->suspect_reason);
  out.set_noise_grey(r->noise_sigma_grey);
  return out;
}

// Poses of a camera of the running service, over DDS.
int LocateLive(const Args& args) {
  const std::string camera = *args.Get("--camera");
  const auto count = args.GetDouble("--count", 1);
  if (!count || *count < 1) return Fail("--count must be >= 1", kExitUsage);
  const auto timeout_s = args.GetDouble("--timeout", 10);
  int status = kExitOk;
  auto client = OpenClient(args, &status);
  if (!client) return status;
  const bool follow = args.Has("--follow");
  // Poses arrive on the subscription's thread; printed here, in order.
  std::mutex mutex;
  std::condition_variable arrived;
  std::deque<Pose> queue;
  auto subscription = client->subscribe_poses(
      [&](const Pose& p) {
        std::lock_guard<std::mutex> lock(mutex);
        queue.push_back(p);
        arrived.notify_one();
      },
      camera);
  if (!subscription) return Fail(subscription.error());
  int printed = 0;
  while (follow || printed < *count) {
    std::unique_lock<std::mutex> lock(mutex);
    if (!arrived.wait_for(lock, std::chrono::duration<double>(*timeout_s),
                          [&] { return !queue.empty(); })) {
      return Fail("no pose from camera '" + camera + "' on DDS domain " +
                      std::to_string(static_cast<int>(*args.GetDouble("--domain", 0))) +
                      " within " + std::to_string(static_cast<int>(*timeout_s)) +
                      " s: is monocled running with that camera and domain?",
                  kExitFailure);
    }
    const Pose pose = std::move(queue.front());
    queue.pop_front();
    lock.unlock();
    if (args.Has("--json")) {
      std::cout << ToJson(ToLiveOutput(pose)) << std::endl;
    } else if (!pose.valid) {
      std::cout << camera << " frame " << pose.frame_sequence << "  error: " << pose.error
                << std::endl;
    } else {
      std::cout << std::fixed << std::setprecision(4) << camera << " frame " << pose.frame_sequence
                << "  x=" << pose.x_m << " y=" << pose.y_m << " z=" << pose.z_m
                << " m  pan=" << pose.pan_rad << " tilt=" << pose.tilt_rad
                << " swing=" << pose.swing_rad << " rad  rms " << std::setprecision(3)
                << pose.rms_px << " px  " << (pose.tracked ? "tracked" : "detected")
                << (pose.suspect ? "  SUSPECT: " + pose.suspect_reason : "") << std::endl;
    }
    ++printed;
  }
  return kExitOk;
}

int Locate(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kLocateHelp;
    return kExitOk;
  }
  auto args =
      Args::Parse(argv, {{"--calibration", "--ceiling-distance", "--overlay", "--camera", "--count",
                          "--domain", "--timeout", "--security", "--detect-every"},
                         {"--json", "--follow", "--track"}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (args->Has("--camera")) return LocateLive(*args);
  if (args->positionals().empty()) return Fail("no IMAGE given (see --help)", kExitUsage);
  const auto cal_path = args->Require("--calibration");
  if (!cal_path) return Fail(cal_path.error(), kExitUsage);
  const auto calibration = LoadCalibrationFile(*cal_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  double zc = calibration->ceiling_distance_m.value_or(0);
  if (args->Get("--ceiling-distance")) {
    const auto z = args->GetDouble("--ceiling-distance", 0);
    if (!z || !(*z > 0))
      return Fail("--ceiling-distance must be a positive distance in metres", kExitUsage);
    zc = *z;
  }
  if (!(zc > 0)) {
    return Fail(
        "the camera-to-ceiling distance is unknown: give --ceiling-distance Z (metres) or add "
        "corner { ceiling_distance: Z } to " +
            *cal_path,
        kExitUsage);
  }
  const auto overlay = args->Get("--overlay");
  if (overlay) {
    std::error_code ec;
    std::filesystem::create_directories(*overlay, ec);
    if (ec)
      return Fail("cannot create overlay folder '" + *overlay + "': " + ec.message(), kExitFailure);
  }
  const bool json = args->Has("--json");
  const auto detect_every = args->GetDouble("--detect-every", 30);
  if (!detect_every || *detect_every < 1 || *detect_every != std::floor(*detect_every))
    return Fail("--detect-every must be a whole number of images >= 1", kExitUsage);
  CornerTrackerOptions tracking;
  tracking.detect_every_n_frames = static_cast<int>(*detect_every);
  std::optional<CornerTracker> tracker;
  if (args->Has("--track")) tracker.emplace(calibration->intrinsics, zc, tracking);
  bool any_failed = false;
  for (const auto& path : args->positionals()) {
    const auto image = ReadGreyImage(path);
    Result<CornerLocation> result = !image    ? Result<CornerLocation>(image.error())
                                    : tracker ? tracker->Process(*image)
                                              : LocateCorner(*image, calibration->intrinsics, zc);
    if (!image && tracker) tracker->Reset();  // a gap in the sequence
    any_failed |= !result.ok();
    if (overlay && image) WriteOverlay(*overlay, path, *image, result);
    if (json) {
      std::cout << ToJson(ToOutput(path, result)) << std::endl;
      continue;
    }
    if (!result) {
      std::cout << path << "  error: " << result.error().message << std::endl;
      continue;
    }
    const auto& p = result->pose;
    const auto s = result->Sigma();
    std::cout << std::fixed << std::setprecision(4) << path << "  x=" << p.x_m << " y=" << p.y_m
              << " z=" << p.z_m << " m  pan=" << p.pan_rad << " tilt=" << p.tilt_rad
              << " swing=" << p.swing_rad << " rad  (1σ " << s[0] << " " << s[1] << " m, " << s[2]
              << " " << s[3] << " " << s[4] << " rad)  corner " << std::setprecision(1)
              << result->corner_px.x() << "," << result->corner_px.y() << " px  rms "
              << std::setprecision(3) << result->rms_px << " px  " << ToString(result->source);
    if (result->suspect) std::cout << "  SUSPECT: " << result->suspect_reason;
    std::cout << std::endl;
  }
  return any_failed ? kExitFailure : kExitOk;
}

}  // namespace

int CornerCommand(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << "Usage: monocle corner locate ...  (monocle corner locate --help)\n";
    return args.empty() ? kExitUsage : kExitOk;
  }
  if (args[0] == "locate") return Locate({args.begin() + 1, args.end()});
  return Fail("unknown corner command '" + args[0] + "' (locate)", kExitUsage);
}

}  // namespace monocle::cli
