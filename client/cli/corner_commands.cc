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
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "client/cli/calibration_warnings.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/corner_output.h"
#include "client/cli/corner_setup.h"
#include "client/cli/live.h"
#include "client/cli/map_output.h"
#include "client/cli/shared_options.h"
#include "idl/cli_output.pb.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle::cli {
namespace {

struct LocateArgs {
  std::vector<std::string> images;
  std::string calibration_path;
  CornerArgs corner;
  std::optional<std::string> overlay;
  bool track = false;
  bool json = false;
  LiveOptions live;
  int count = 1;
  bool follow = false;
};

constexpr const char* kLocateAbout =
    R"(Finds the ceiling corner (two ceiling edges and the vertical wall edge meeting in a Y) in
each image and computes the camera's pose in the corner frame (Chou & Tsai 1986): origin
at the corner, X and Y along the ceiling edges, Z down the vertical edge, room at x, y,
z > 0. Position x, y, z in metres (z = the camera-to-ceiling distance), pan, tilt, swing in
radians as the paper's eq. (1) (tilt 0 looks straight up, swing 0 is an upright camera).
With --map, the robot's pose in a room map from whichever corner is in view, and which.)";

constexpr const char* kLocateFooter =
    R"(Every pose says how well the image supports it: per edge the length found, its contrast
against the image's noise (noise_grey: as an edge measurement averaging pixels sees it, so
JPEG frames and raw frames read alike), how far its points lie from the pose's line, and
what part of the position's variance it gives (position_variance_share: the edge that
limits the pose). A pose with an edge fainter than that noise, whose edges disagree, or
that is weakly determined (1 sigma above 1.25 % of the distance; the reason names the edge
giving most of it) is printed as SUSPECT with the reason; it is never dropped silently. So
is a pose that rolls the camera more than 45 degrees about its axis (a floor corner read
as the ceiling's): a camera mounted rolled further sets corner { max_swing: RADIANS } in its
calibration file. A Y flagged for its edges or its roll gives way to the next Y in the
image whose pose is flagged for nothing but its 1 sigma; only where there is none is it
printed, flagged. With --mount, a pose that tips the robot more than 1 degree from level,
and more than its own 1 sigma allows, is SUSPECT and left as solved.
Where the 1 sigma is over 0.4 % of the distance, the shading beside the edges is read and
the shift it causes (shading_shift_m, x and y in metres) is removed and counted in the
1 sigma: a surface brightening away from a faint edge moves all its points one way.
Over 0.6 %, the edges are first measured again along the fitted lines with a wider filter
(1.9x the edge's blur, not 1.6x), which locates a faint edge more precisely; its larger
shading bias is what the correction then removes (measured_again in the JSON).

Any image OpenCV reads (PNG, PGM, JPEG, ...). An image without a corner is reported and
the others are still processed; the exit status is 1 if any image failed, or if an image's
pose in the map is not decided.)";

void DeclareLocate(CommandLine& line, LocateArgs* a) {
  line.Footer(kLocateFooter);
  line.Flag("--json", &a->json,
            "one JSON object per line: image x y z pan tilt swing quaternion corner_px rms_px "
            "sigma lines (with each edge's support) source suspect [suspect_reason] noise_grey "
            "[shading_shift_m] [measured_again] [map] [level_error_deg level_sigma_deg] [base], or "
            "image error; live: the same inside {camera, sequence, capture_time_ns, "
            "time_source, pose}");
  line.InForms({0});
  line.Positionals("IMAGE", &a->images, "an image of the ceiling corner");
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "intrinsics (pixels are undistorted first) and optionally corner { "
            "ceiling_distance }");
  line.Require("--calibration");
  DeclareCeilingDistance(line, &a->corner, "overrides the calibration file's");
  line.Text("--overlay", &a->overlay, "DIR",
            "write DIR/<image>.overlay.png: the edges measured (thick), the edges the pose "
            "predicts (thin white, to the border), each edge's support (length, coverage, "
            "contrast/noise, misfit, its part of the position's variance), the pose; without a "
            "pose, the straight edges seen and why");
  line.Flag("--track", &a->track,
            "the images are an ordered sequence (frames of a video): predict the three edges "
            "from the previous pose and measure them there first; a full detection when that "
            "fails, when the tracked pose is suspect, and every --detect-every N images. Each "
            "result says \"tracked\" or \"detected\"");
  DeclareCornerSetup(line, &a->corner, "images");
  line.Form("Live, from the running service (monocled) over DDS, instead of IMAGE files",
            "a live camera's poses come as monocled's configuration makes them (mount, "
            "level_sigma_deg, room_map, initial_pose)");
  line.Text("--camera", &a->live.camera, "ID", "the camera's poses as monocled publishes them");
  line.Require("--camera");
  line.Whole("--count", &a->count, "N", "stop after N poses", In("poses").AtLeast(1));
  line.Flag("--follow", &a->follow, "print poses until Ctrl-C");
  DeclareServiceOptions(line, &a->live, "give up after S seconds without a pose");
}

// 1 sigma of the pose's parameter `i` (x, y, pan, tilt, swing), from its covariance.
double Sigma(const Pose& pose, int i) { return std::sqrt(std::max(0.0, pose.covariance[6 * i])); }

// Poses of a camera of the running service, over DDS.
int LocateLive(const LocateArgs& a) {
  const std::string& camera = *a.live.camera;
  const double timeout_s = a.live.timeout_s;
  int status = kExitOk;
  auto client = OpenClient(a.live, &status);
  if (!client) return status;
  // A wrong name or a floor camera is said at once, not after --timeout without a pose.
  if (auto cam = FindServiceCamera(*client, camera, a.live.domain, "corner"); !cam)
    return Fail(cam.error(), kExitFailure);
  const bool follow = a.follow;
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
      camera,
      [](const std::string& ignored) {
        std::cerr << "monocle: warning: " << ignored << std::endl;
      });
  if (!subscription) return Fail(subscription.error());
  const bool sigma_excludes_intrinsics = WarnIfLiveIntrinsicsHaveNoCovariance(*client, camera);
  int printed = 0;
  while (follow || printed < a.count) {
    std::unique_lock<std::mutex> lock(mutex);
    if (!arrived.wait_for(lock, std::chrono::duration<double>(timeout_s),
                          [&] { return !queue.empty(); })) {
      return Fail("no pose from camera '" + camera + "' on DDS domain " +
                      std::to_string(a.live.domain) + " within " +
                      std::to_string(static_cast<int>(timeout_s)) +
                      " s: is monocled running with that camera and domain?",
                  kExitFailure);
    }
    const Pose pose = std::move(queue.front());
    queue.pop_front();
    lock.unlock();
    if (a.json) {
      proto::LivePoseOutput out = ToLiveOutput(pose);
      if (pose.valid) out.mutable_pose()->set_sigma_excludes_intrinsics(sigma_excludes_intrinsics);
      std::cout << ToJson(out) << std::endl;
    } else if (!pose.valid) {
      std::cout << camera << " frame " << pose.frame_sequence << "  error: " << pose.error
                << std::endl;
    } else {
      std::cout << std::fixed << std::setprecision(4) << camera << " frame " << pose.frame_sequence
                << "  x=" << pose.x_m << " y=" << pose.y_m << " z=" << pose.z_m
                << " m  pan=" << pose.pan_rad << " tilt=" << pose.tilt_rad
                << " swing=" << pose.swing_rad << " rad  (1σ " << Sigma(pose, 0) << " "
                << Sigma(pose, 1) << " m, " << Sigma(pose, 2) << " " << Sigma(pose, 3) << " "
                << Sigma(pose, 4) << " rad)  rms " << std::setprecision(3) << pose.rms_px << " px  "
                << (pose.tracked ? "tracked" : "detected");
      if (pose.level_sigma_rad > 0) {
        std::cout << std::setprecision(2) << "  level "
                  << pose.level_error_rad * 180 / std::numbers::pi << " deg off as solved (1σ "
                  << pose.level_sigma_rad * 180 / std::numbers::pi << " deg)";
      }
      if (pose.base_known) std::cout << BaseText(ToLiveOutput(pose).pose().base());
      std::cout << (pose.suspect ? "  SUSPECT: " + pose.suspect_reason : "") << std::endl;
      if (pose.map_status == MapStatus::kLocated) {
        std::cout << std::setprecision(4) << "  map: " << pose.map_corner << " (room "
                  << pose.map_room << ")  base x=" << pose.map_x_m << " y=" << pose.map_y_m
                  << " m heading=" << std::setprecision(2)
                  << pose.map_heading_rad * 180 / std::numbers::pi << " deg" << std::endl;
      } else if (pose.map_status != MapStatus::kNone) {
        std::cout << "  map: " << ToString(pose.map_status) << ": " << pose.map_reason << std::endl;
      }
    }
    ++printed;
  }
  return kExitOk;
}

int Locate(const std::vector<std::string>& argv) {
  LocateArgs a;
  CommandLine line("corner locate", kLocateAbout);
  DeclareLocate(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  if (a.live.camera) return LocateLive(a);
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  WarnIfIntrinsicsHaveNoCovariance(a.calibration_path, *calibration);
  auto setup = CornerSetupFrom(a.corner);
  if (!setup) return Fail(setup.error(), UsageOrFailure(setup.error()));
  CornerPipelineOptions options = std::move(*setup);
  // In a map each corner's ceiling distance follows from the mount: solve at any one of
  // them (the map scales the pose to each corner's).
  if (!options.room_map) {
    const auto z =
        CeilingDistanceM(a.corner, calibration->ceiling_distance_m, a.calibration_path,
                         " (or locate in a room map: --map MAP.pbtxt --mount MOUNT.pbtxt)");
    if (!z) return Fail(z.error(), kExitUsage);
    options.ceiling_distance_m = *z;
  }
  const auto& overlay = a.overlay;
  if (overlay) {
    std::error_code ec;
    std::filesystem::create_directories(*overlay, ec);
    if (ec)
      return Fail("cannot create overlay folder '" + *overlay + "': " + ec.message(), kExitFailure);
  }
  const bool json = a.json;
  options.track = a.track;
  CornerPipeline pipeline(std::move(options));
  bool any_failed = false;
  for (const auto& path : a.images) {
    const auto image = ReadGreyImage(path);
    CornerPipelineResult located;
    if (image) {
      located = pipeline.Process(*image, *calibration);
    } else {
      located.corner = image.error();
      pipeline.Missed();  // a gap in the sequence
    }
    const Result<CornerLocation>& result = located.corner;
    const std::optional<MapLocation>& where = located.map;
    any_failed |= !result.ok();
    if (where) any_failed |= !where->decided();
    if (overlay && image)
      WriteCornerOverlay(*overlay, path, *image, calibration->intrinsics, result);
    if (json) {
      proto::CornerOutput out = ToCornerOutput(path, result);
      if (where) *out.mutable_map() = ToMapLocationOutput(*where);
      std::cout << ToJson(out) << std::endl;
      continue;
    }
    if (!result) {
      std::cout << path << "  error: " << result.error().message << std::endl;
      continue;
    }
    std::cout << CornerResultLine(path, *result) << std::endl;
    if (where) std::cout << "  " << MapLocationLine(*where) << std::endl;
  }
  return any_failed ? kExitFailure : kExitOk;
}

}  // namespace

int CornerCommand(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << "Usage: monocle corner locate ...    (monocle corner locate --help)\n"
                 "       monocle corner fit-mount ... (monocle corner fit-mount --help)\n";
    return args.empty() ? kExitUsage : kExitOk;
  }
  if (args[0] == "locate") return Locate({args.begin() + 1, args.end()});
  if (args[0] == "fit-mount") return FitMountCommand({args.begin() + 1, args.end()});
  return Fail("unknown corner command '" + args[0] + "' (locate, fit-mount)", kExitUsage);
}

}  // namespace monocle::cli
