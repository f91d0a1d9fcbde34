// monocle replay: a recording's frames through the corner pipeline monocled runs.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "camera/recording_source.h"
#include "client/cli/args.h"
#include "client/cli/commands.h"
#include "client/cli/corner_output.h"
#include "client/cli/corner_setup.h"
#include "client/cli/map_output.h"
#include "client/cli/progress.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle::cli {
namespace {

constexpr const char* kReplayHelp =
    R"help(Usage: monocle replay FILE.mcap [--camera ID] [--rate X] [--json]
                      [--calibration CAL.pbtxt] [--ceiling-distance Z] [--detect-every N]
                      [--map MAP.pbtxt --mount MOUNT.pbtxt [--prior X,Y,HEADING_DEG]]
                      [--level-sigma DEG]

Runs the recorded frames of a recording (monocle record --frames every|N, or monocled
--record-frames) through the corner pipeline monocled runs: the three edges tracked from
frame to frame, a full detection on the first frame, when tracking fails, on a suspect pose
and every N frames. One pose per frame, in the corner frame (metres, radians), like
`monocle corner locate`. Every frame is processed, in recorded order, whatever the pace, so
a replay gives the same poses every time (monocled live skips frames while it is busy).

  --camera ID          only this camera (default: every corner camera with frames)
  --rate X             0 (default): as fast as poses are computed; 1: at the recorded pace;
                       2: twice as fast
  --json               one JSON object per line, as `monocle corner locate --camera ID
                       --json`: camera, sequence (the frame's index in the recording, from 0),
                       capture_time_ns (the recorded stamp), time_source "recorded", pose
  --calibration CAL    use these intrinsics (and ceiling distance) instead of the calibration
                       the recording started with
  --ceiling-distance Z camera to ceiling, metres (default: what the service used)
  --detect-every N     a full detection at least every N frames (default 30, as monocled)
  --map MAP --mount MOUNT
                       place every pose in the room map monocled was configured with
                       (room_map, mount): the same map poses it published, frame for frame
  --prior X,Y,DEG      where the robot started in the map (monocled's initial_pose)
  --mount MOUNT alone  combine each pose with the robot's level (monocled's level_sigma_deg)
  --level-sigma DEG    how level the robot stands, 1 sigma in degrees (default 0.3)

Text lines: "<camera> frame N  x=... y=... z=... m  pan=... tilt=... swing=... rad (1σ ...)".
A progress line goes to the terminal when the poses go to a file. `monocle info FILE` lists
what a recording holds; `monocled --replay FILE` serves it over DDS as if live.
Exit status 1 if a frame had no pose or the file is damaged.
)help";

// One camera being replayed: its frames, its pipeline, its next frame (for merging the
// cameras in capture-time order).
struct ReplayedCamera {
  RecordedCamera recorded;
  std::unique_ptr<RecordingSource> source;
  std::optional<CornerPipeline> pipeline;
  CameraCalibration calibration;
  std::optional<Frame> next;
};

bool IsCorner(const RecordedCamera& cam) {
  return cam.role == "corner" || cam.role == "corner+floor" || cam.role.empty();
}

}  // namespace

int ReplayCommand(const std::vector<std::string>& argv) {
  if (WantsHelp(argv)) {
    std::cout << kReplayHelp;
    return kExitOk;
  }
  auto args = Args::Parse(argv, {{"--camera", "--rate", "--calibration", "--ceiling-distance",
                                  "--detect-every", "--map", "--mount", "--prior", "--level-sigma"},
                                 {"--json"}});
  if (!args) return Fail(args.error(), kExitUsage);
  if (args->positionals().size() != 1)
    return Fail("give exactly one FILE.mcap (see --help)", kExitUsage);
  const std::string path = args->positionals()[0];
  const auto rate = args->GetDouble("--rate", 0);
  if (!rate || !(*rate >= 0) || *rate > 1000)
    return Fail("--rate must be 0 (as fast as possible) or a factor up to 1000", kExitUsage);
  const auto detect_every = DetectEvery(*args, "frames");
  if (!detect_every) return Fail(detect_every.error(), kExitUsage);
  const auto level_sigma_rad = LevelSigmaRad(*args);
  if (!level_sigma_rad) return Fail(level_sigma_rad.error(), kExitUsage);
  auto setup = CornerSetupFromArgs(*args, *level_sigma_rad);
  if (!setup) return Fail(setup.error(), UsageOrFailure(setup.error()));
  setup->tracking.detect_every_n_frames = *detect_every;
  std::optional<double> ceiling_override;
  if (args->Get("--ceiling-distance")) {
    const auto z = args->GetDouble("--ceiling-distance", 0);
    if (!z || !(*z > 0))
      return Fail("--ceiling-distance must be a positive distance in metres", kExitUsage);
    ceiling_override = *z;
  }
  std::optional<CameraCalibration> calibration_override;
  if (const auto cal = args->Get("--calibration")) {
    auto loaded = LoadCalibrationFile(*cal);
    if (!loaded) return Fail(loaded.error(), kExitFailure);
    calibration_override = *loaded;
  }

  auto cameras = ListRecordedCameras(path);
  if (!cameras) return Fail(cameras.error(), kExitFailure);
  const auto only = args->Get("--camera");
  std::vector<ReplayedCamera> replayed;
  std::string seen;
  for (const auto& cam : *cameras) {
    seen += (seen.empty() ? "" : ", ") + cam.id + " (" + (cam.role.empty() ? "?" : cam.role) +
            ", " + std::to_string(cam.frames) + " frames)";
    if (only && cam.id != *only) continue;
    if (!IsCorner(cam)) {
      if (only) {
        return Fail("camera '" + cam.id +
                        "' is a floor camera: its frames have no pose to replay; `monocled "
                        "--replay " +
                        path + "` serves its point queries",
                    kExitUsage);
      }
      continue;
    }
    ReplayedCamera r;
    r.recorded = cam;
    replayed.push_back(std::move(r));
  }
  if (replayed.empty()) {
    return Fail(path + ": " +
                    (only ? "no camera '" + *only + "' with frames"
                          : std::string("no corner camera with frames")) +
                    (seen.empty() ? " (the recording has no frames: record with --frames "
                                    "every or N)"
                                  : " (the recording has: " + seen + ")"),
                kExitFailure);
  }
  uint64_t total = 0;
  for (auto& r : replayed) {
    CameraCalibration calibration;
    if (calibration_override) {
      calibration = *calibration_override;
    } else {
      auto parsed = ParseCalibration(r.recorded.calibration_text,
                                     path + " (" + r.recorded.id + "'s recorded calibration)");
      if (r.recorded.calibration_text.empty()) {
        return Fail(path + ": camera '" + r.recorded.id +
                        "' has no calibration in the recording; give --calibration CAL.pbtxt",
                    kExitFailure);
      }
      if (!parsed) return Fail(parsed.error(), kExitFailure);
      calibration = *parsed;
    }
    const double zc = setup->ceiling_distance_m.value_or(ceiling_override.value_or(
        calibration_override
            ? calibration.ceiling_distance_m.value_or(0)
            : r.recorded.ceiling_distance_m.value_or(calibration.ceiling_distance_m.value_or(0))));
    if (!(zc > 0)) {
      return Fail("camera '" + r.recorded.id +
                      "': the camera-to-ceiling distance is unknown; give --ceiling-distance Z "
                      "(metres)",
                  kExitUsage);
    }
    CornerPipelineOptions options = *setup;
    options.ceiling_distance_m = zc;
    r.pipeline.emplace(std::move(options));
    r.calibration = calibration;
    auto source = RecordingSource::Open(path, r.recorded.ros_namespace, ReplayPace{*rate, false});
    if (!source) return Fail(source.error(), kExitFailure);
    r.source = std::move(*source);
    total += r.recorded.frames;
  }

  // Next frame of a camera, waiting as long as its pace asks; nullopt at its end.
  auto advance = [](ReplayedCamera& r) -> Status {
    r.next.reset();
    while (true) {
      auto frame = r.source->Next(std::chrono::milliseconds(1000));
      if (frame) {
        r.next = std::move(*frame);
        return Ok{};
      }
      if (r.source->ended()) return Ok{};
      if (frame.error().code != ErrorCode::kNotFound) return frame.error();
    }
  };
  for (auto& r : replayed) {
    if (Status s = advance(r); !s) return Fail(s.error(), kExitFailure);
  }
  const bool json = args->Has("--json");
  // On a terminal the poses themselves show the progress: a line only when they go to a file.
  ProgressLine progress("replaying frames", total,
                        isatty(STDERR_FILENO) == 1 && isatty(STDOUT_FILENO) == 0);
  uint64_t done = 0;
  bool any_failed = false;
  while (true) {
    // The camera whose next frame was captured first.
    ReplayedCamera* first = nullptr;
    for (auto& r : replayed) {
      if (r.next && (first == nullptr || r.next->capture_time_ns < first->next->capture_time_ns))
        first = &r;
    }
    if (first == nullptr) break;
    const Frame frame = std::move(*first->next);
    const CornerPipelineResult located = first->pipeline->Process(frame.grey, first->calibration);
    const Result<CornerLocation>& result = located.corner;
    any_failed |= !result.ok();
    if (json) {
      proto::LivePoseOutput out;
      out.set_camera(first->recorded.id);
      out.set_sequence(frame.sequence);
      out.set_capture_time_ns(frame.capture_time_ns);
      out.set_time_source("recorded");
      *out.mutable_pose() = ToCornerOutput("", result);
      if (located.map) *out.mutable_pose()->mutable_map() = ToMapLocationOutput(*located.map);
      std::cout << ToJson(out) << std::endl;
    } else {
      const std::string label = first->recorded.id + " frame " + std::to_string(frame.sequence);
      if (result) {
        std::cout << CornerResultLine(label, *result) << std::endl;
        if (located.map) std::cout << "  " << MapLocationLine(*located.map) << std::endl;
      } else {
        std::cout << label << "  error: " << result.error().message << std::endl;
      }
    }
    progress.Update(++done);
    if (Status s = advance(*first); !s) {
      progress.Done();
      return Fail(s.error(), kExitFailure);
    }
  }
  progress.Done();
  return any_failed ? kExitFailure : kExitOk;
}

}  // namespace monocle::cli
