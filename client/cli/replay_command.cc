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
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/corner_output.h"
#include "client/cli/corner_setup.h"
#include "client/cli/map_output.h"
#include "client/cli/progress.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle::cli {
namespace {

constexpr const char* kReplayAbout =
    R"text(Runs the recorded frames of a recording (monocle record --frames every|N, or monocled
--record-frames) through the corner pipeline monocled runs: the three edges tracked from
frame to frame, a full detection on the first frame, when tracking fails, on a suspect pose
and every N frames. One pose per frame, in the corner frame (metres, radians), like
`monocle corner locate`. Every frame is processed, in recorded order, whatever the pace, so
a replay gives the same poses every time (monocled live skips frames while it is busy).
Give --map, --mount, --prior and --level-sigma as monocled was configured (room_map, mount,
initial_pose, level_sigma_deg) to get the map poses it published, frame for frame.)text";

constexpr const char* kReplayFooter =
    R"text(Text lines: "<camera> frame N  x=... y=... z=... m  pan=... tilt=... swing=... rad (1σ ...)".
A progress line goes to the terminal when the poses go to a file. `monocle info FILE` lists
what a recording holds; `monocled --replay FILE` serves it over DDS as if live.
Exit status 1 if a frame had no pose or the file is damaged.)text";

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

// What the command line asks of a replay, checked once.
struct ReplayOptions {
  std::string path;
  double rate = 0;
  std::optional<std::string> only_camera;
  bool json = false;
  CornerPipelineOptions pipeline;  // mount, level, map, tracking
  std::optional<double> ceiling_override;
  std::optional<CameraCalibration> calibration_override;
};

struct ReplayArgs {
  std::vector<std::string> file;
  std::optional<std::string> camera, calibration_path;
  double rate = 0;
  bool json = false;
  CornerArgs corner;
};

void DeclareReplay(CommandLine& line, ReplayArgs* a) {
  line.Footer(kReplayFooter);
  line.Positionals("FILE.mcap", &a->file, "the recording", 1, 1);
  line.Text("--camera", &a->camera, "ID",
            "only this camera (default: every corner camera with frames)");
  line.Number("--rate", &a->rate, "X",
              "0: as fast as poses are computed; 1: at the recorded pace; 2: twice as fast",
              In("times the recorded pace").Between(0, 1000));
  line.Flag("--json", &a->json,
            "one JSON object per line, as `monocle corner locate --camera ID --json`: camera, "
            "sequence (the frame's index in the recording, from 0), capture_time_ns (the "
            "recorded stamp), time_source \"recorded\", pose");
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "use these intrinsics (and ceiling distance) instead of the calibration the "
            "recording started with");
  DeclareCeilingDistance(line, &a->corner, "default: what the service used");
  DeclareCornerSetup(line, &a->corner, "frames");
}

// kExitOk with `out` filled, -1 when the help was printed, or the exit status of the mistake
// (already reported).
int ParseReplayOptions(const std::vector<std::string>& argv, ReplayOptions* out) {
  ReplayArgs a;
  CommandLine line("replay", kReplayAbout);
  DeclareReplay(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now == kExitOk ? -1 : *exit_now;
  out->path = a.file[0];
  out->rate = a.rate;
  auto setup = CornerSetupFrom(a.corner);
  if (!setup) return Fail(setup.error(), UsageOrFailure(setup.error()));
  out->pipeline = std::move(*setup);
  out->ceiling_override = a.corner.ceiling_distance_m;
  if (a.calibration_path) {
    auto loaded = LoadCalibrationFile(*a.calibration_path);
    if (!loaded) return Fail(loaded.error(), kExitFailure);
    out->calibration_override = *loaded;
  }
  out->only_camera = a.camera;
  out->json = a.json;
  return kExitOk;
}

// The recording's corner cameras to replay (only --camera's if given), or the exit status.
int SelectCameras(const ReplayOptions& o, std::vector<ReplayedCamera>* replayed) {
  auto cameras = ListRecordedCameras(o.path);
  if (!cameras) return Fail(cameras.error(), kExitFailure);
  std::string seen;
  for (const auto& cam : *cameras) {
    seen += (seen.empty() ? "" : ", ") + cam.id + " (" + (cam.role.empty() ? "?" : cam.role) +
            ", " + std::to_string(cam.frames) + " frames)";
    if (o.only_camera && cam.id != *o.only_camera) continue;
    if (!IsCorner(cam)) {
      if (o.only_camera) {
        return Fail("camera '" + cam.id +
                        "' is a floor camera: its frames have no pose to replay; `monocled "
                        "--replay " +
                        o.path + "` serves its point queries",
                    kExitUsage);
      }
      continue;
    }
    ReplayedCamera r;
    r.recorded = cam;
    replayed->push_back(std::move(r));
  }
  if (replayed->empty()) {
    return Fail(o.path + ": " +
                    (o.only_camera ? "no camera '" + *o.only_camera + "' with frames"
                                   : std::string("no corner camera with frames")) +
                    (seen.empty() ? " (the recording has no frames: record with --frames "
                                    "every or N)"
                                  : " (the recording has: " + seen + ")"),
                kExitFailure);
  }
  return kExitOk;
}

// Each camera's calibration, pipeline and frames; kExitOk or the exit status.
int OpenCamera(const ReplayOptions& o, ReplayedCamera* r) {
  CameraCalibration calibration;
  if (o.calibration_override) {
    calibration = *o.calibration_override;
  } else {
    if (r->recorded.calibration_text.empty()) {
      return Fail(o.path + ": camera '" + r->recorded.id +
                      "' has no calibration in the recording; give --calibration CAL.pbtxt",
                  kExitFailure);
    }
    auto parsed = ParseCalibration(r->recorded.calibration_text,
                                   o.path + " (" + r->recorded.id + "'s recorded calibration)");
    if (!parsed) return Fail(parsed.error(), kExitFailure);
    calibration = *parsed;
  }
  // A map's ceiling distance first, then --ceiling-distance, then what the service used.
  const double recorded_zc =
      o.calibration_override
          ? calibration.ceiling_distance_m.value_or(0)
          : r->recorded.ceiling_distance_m.value_or(calibration.ceiling_distance_m.value_or(0));
  const double zc =
      o.pipeline.ceiling_distance_m.value_or(o.ceiling_override.value_or(recorded_zc));
  if (!(zc > 0)) {
    return Fail("camera '" + r->recorded.id +
                    "': the camera-to-ceiling distance is unknown; give --ceiling-distance Z "
                    "(metres)",
                kExitUsage);
  }
  CornerPipelineOptions options = o.pipeline;
  options.ceiling_distance_m = zc;
  r->pipeline.emplace(std::move(options));
  r->calibration = calibration;
  auto source = RecordingSource::Open(o.path, r->recorded.ros_namespace, ReplayPace{o.rate, false});
  if (!source) return Fail(source.error(), kExitFailure);
  r->source = std::move(*source);
  return kExitOk;
}

// Next frame of a camera, waiting as long as its pace asks; none at its end.
Status Advance(ReplayedCamera& r) {
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
}

void PrintPose(const ReplayOptions& o, const ReplayedCamera& camera, const Frame& frame,
               const CornerPipelineResult& located) {
  const Result<CornerLocation>& result = located.corner;
  if (o.json) {
    proto::LivePoseOutput out;
    out.set_camera(camera.recorded.id);
    out.set_sequence(frame.sequence);
    out.set_capture_time_ns(frame.capture_time_ns);
    out.set_time_source("recorded");
    *out.mutable_pose() = ToCornerOutput("", result);
    if (located.map) *out.mutable_pose()->mutable_map() = ToMapLocationOutput(*located.map);
    std::cout << ToJson(out) << std::endl;
    return;
  }
  const std::string label = camera.recorded.id + " frame " + std::to_string(frame.sequence);
  if (!result) {
    std::cout << label << "  error: " << result.error().message << std::endl;
    return;
  }
  std::cout << CornerResultLine(label, *result) << std::endl;
  if (located.map) std::cout << "  " << MapLocationLine(*located.map) << std::endl;
}

// Every camera's frames through its pipeline, in capture-time order.
int Replay(const ReplayOptions& o, std::vector<ReplayedCamera>& replayed, uint64_t total) {
  for (auto& r : replayed) {
    if (Status s = Advance(r); !s) return Fail(s.error(), kExitFailure);
  }
  // On a terminal the poses themselves show the progress: a line only when they go to a file.
  ProgressLine progress("replaying frames", total,
                        isatty(STDERR_FILENO) == 1 && isatty(STDOUT_FILENO) == 0);
  uint64_t done = 0;
  bool any_failed = false;
  while (true) {
    ReplayedCamera* first = nullptr;  // the camera whose next frame was captured first
    for (auto& r : replayed) {
      if (r.next && (first == nullptr || r.next->capture_time_ns < first->next->capture_time_ns))
        first = &r;
    }
    if (first == nullptr) break;
    const Frame frame = std::move(*first->next);
    const CornerPipelineResult located =
        first->pipeline->Process(frame.grey, first->calibration, CaptureTimeS(frame));
    any_failed |= !located.corner.ok();
    PrintPose(o, *first, frame, located);
    progress.Update(++done);
    if (Status s = Advance(*first); !s) {
      progress.Done();
      return Fail(s.error(), kExitFailure);
    }
  }
  progress.Done();
  return any_failed ? kExitFailure : kExitOk;
}

}  // namespace

int ReplayCommand(const std::vector<std::string>& argv) {
  ReplayOptions options;
  if (int status = ParseReplayOptions(argv, &options); status != kExitOk)
    return status < 0 ? kExitOk : status;  // -1: the help was asked for and printed
  std::vector<ReplayedCamera> replayed;
  if (int status = SelectCameras(options, &replayed); status != kExitOk) return status;
  uint64_t total = 0;
  for (auto& r : replayed) {
    if (int status = OpenCamera(options, &r); status != kExitOk) return status;
    total += r.recorded.frames;
  }
  return Replay(options, replayed, total);
}

}  // namespace monocle::cli
