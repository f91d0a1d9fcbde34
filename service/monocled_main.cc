// monocled: the measurement service. Reads its configuration, starts its cameras and serves
// poses, calibrations, status and requests over Cyclone DDS until SIGINT or SIGTERM.
#include <malloc.h>
#include <signal.h>

#include <csignal>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <string>

#include "camera/sim/sim_calibrations.h"
#include "idl/protocol/dds.h"
#include "idl/record/recorder.h"
#include "service/server/replay_setup.h"
#include "service/server/service.h"
#include "service/server/service_config.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: monocled [--config FILE.pbtxt] [--domain D] [--security DIR] [--state-dir DIR]
                [--record FILE.mcap [--record-frames none|every|N] [--record-zstd]]
                [--replay FILE.mcap [--replay-rate X] [--replay-loop]] [--print-config]
                [--version]

The monocle service: measures robot poses from ceiling corners and floor points from its
cameras and serves them over Cyclone DDS (topics: service/README.md).

  --config FILE    text-protobuf configuration (schema idl/service_config.proto): cameras
                   (Aravis id, IP, serial, or sim-corner / sim-floor), their role (CORNER,
                   FLOOR, CORNER_AND_FLOOR), calibration files, GenICam features, DDS domain.
                   Without it: the embedded default, the two in-process simulated cameras
                   sim-corner and sim-floor.
  --domain D       DDS domain id, overrides the configuration's (0..232)
  --security DIR   DDS Security: the service's identity directory of a keystore made by
                   `monocle security init` (overrides the configuration's security_dir)
  --state-dir DIR  where the embedded default keeps its calibration files (default
                   $XDG_STATE_HOME/monocle, else ~/.local/state/monocle)
  --record FILE.mcap  record what the service publishes (poses, calibrations, status,
                   requests and replies, frames) into an MCAP file, in-process; the file is
                   closed with its index at stop. A full disk stops the recording (logged),
                   never the service. Same content as `monocle record`.
  --record-frames MODE  none (default), every frame, or every Nth. Frames are recorded at
                   the camera's rate: this lifts image_max_rate_hz of the recorded cameras.
  --record-zstd    compress the recording losslessly (zstd chunks)
  --replay FILE.mcap  serve a recording as if its cameras were live: every camera with
                   frames in it (`monocle record --frames every`, `monocled --record-frames`),
                   under its recorded id and ROS namespace, with the calibration and role it
                   had when the recording started (a copy in STATE-DIR/replay/). Poses are
                   computed again from the frames; capture times are the recorded ones. At
                   the end of the file the camera's state is "stopped". Not with --config.
  --replay-rate X  1 (default): at the recorded pace; 2 twice as fast; 0 as fast as frames
                   can be read (monocled still processes only the newest frame, as live)
  --replay-loop    start the recording again at its end
  --print-config   print the embedded default configuration as a file to start from: its
                   calibration files written to the state directory and named there in
                   full, so `monocled --print-config > my.pbtxt; monocled --config my.pbtxt`
                   starts as the default does
  --version        print the version and exit

CYCLONEDDS_URI configures Cyclone DDS (docker/cyclonedds-loopback.xml: loopback only).
SIGINT or SIGTERM stop it cleanly.
)";

std::string DefaultStateDir() {
  if (const char* xdg = std::getenv("XDG_STATE_HOME"); xdg != nullptr && *xdg != '\0')
    return std::string(xdg) + "/monocle";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::string(home) + "/.local/state/monocle";
  return "/tmp/monocle-state";
}

int Usage(const std::string& why) {
  std::cerr << "monocled: error: " << why << " (see --help)\n";
  return 2;
}

// A stop signal arrived (it is blocked, so it waits as pending).
bool StopRequested() {
  sigset_t pending;
  sigpending(&pending);
  return sigismember(&pending, SIGINT) == 1 || sigismember(&pending, SIGTERM) == 1;
}

// What the command line asks for.
struct MonocledOptions {
  std::string config_path, state_dir = DefaultStateDir(), security_dir;
  std::optional<int> domain;
  std::string record_path;
  monocle::record::RecordOptions record_options;
  std::string replay_path;
  monocle::ReplayPace replay_pace;
  bool replay_rate_given = false;
  bool print_config = false;
};

// --print-config: the embedded default as a configuration file that starts as it is: its
// calibration files written to the state directory and named there in full.
int PrintConfig(const MonocledOptions& o) {
  if (auto s = monocle::EnsureSimulatorCalibrations(o.state_dir); !s) {
    std::cerr << "monocled: error: " << s.error() << "\n";
    return 1;
  }
  std::error_code ec;
  const auto dir = std::filesystem::absolute(o.state_dir, ec).lexically_normal().string();
  std::cout << monocle::EmbeddedDefaultConfig(ec ? o.state_dir : dir);
  return 0;
}

// --record-frames none|every|N; false for anything else.
bool ParseRecordFrames(const std::string& mode, int* frames_every) {
  char* end = nullptr;
  const long n = std::strtol(mode.c_str(), &end, 10);
  if (mode == "none") {
    *frames_every = 0;
  } else if (mode == "every") {
    *frames_every = 1;
  } else if (!mode.empty() && *end == '\0' && n >= 1 && n <= 1000000) {
    *frames_every = static_cast<int>(n);
  } else {
    return false;
  }
  return true;
}

// The options, or the exit status when monocled is to stop here (--help, --print-config, a
// mistake on the command line).
std::optional<int> ParseOptions(int argc, char** argv, MonocledOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (a == "--version") {
      std::cout << "monocled " MONOCLE_VERSION "\n";
      return 0;
    } else if (a == "--print-config") {
      o->print_config = true;
    } else if (a == "--config" && has_value) {
      o->config_path = argv[++i];
    } else if (a == "--security" && has_value) {
      o->security_dir = argv[++i];
    } else if (a == "--state-dir" && has_value) {
      o->state_dir = argv[++i];
    } else if (a == "--domain" && has_value) {
      char* end = nullptr;
      const long d = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || d < 0 || d > 232) return Usage("--domain must be 0..232");
      o->domain = static_cast<int>(d);
    } else if (a == "--record" && has_value) {
      o->record_path = argv[++i];
    } else if (a == "--replay" && has_value) {
      o->replay_path = argv[++i];
    } else if (a == "--replay-rate" && has_value) {
      char* end = nullptr;
      const double rate = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(rate >= 0) || rate > 1000)
        return Usage("--replay-rate must be 0 (no waiting) or a factor up to 1000, e.g. 1 or 0.5");
      o->replay_pace.rate = rate;
      o->replay_rate_given = true;
    } else if (a == "--replay-loop") {
      o->replay_pace.loop = true;
    } else if (a == "--record-zstd") {
      o->record_options.zstd = true;
    } else if (a == "--record-frames" && has_value) {
      if (!ParseRecordFrames(argv[++i], &o->record_options.frames_every))
        return Usage("--record-frames must be none, every or a whole number N >= 1");
    } else if (a == "--config" || a == "--state-dir" || a == "--domain" || a == "--security" ||
               a == "--record" || a == "--record-frames" || a == "--replay" ||
               a == "--replay-rate") {
      return Usage(a + " needs a value");
    } else {
      return Usage("unknown option " + a);
    }
  }
  if (!o->replay_path.empty() && !o->config_path.empty())
    return Usage("--replay serves the recording's own cameras and calibrations: not with --config");
  if (o->replay_path.empty() && (o->replay_rate_given || o->replay_pace.loop))
    return Usage("--replay-rate and --replay-loop need --replay FILE.mcap");
  if (o->record_options.frames_every > 0 && o->record_path.empty())
    return Usage("--record-frames needs --record FILE.mcap");
  return std::nullopt;
}

// The cameras to serve: a recording's, the configuration's, or the embedded default's (its
// simulators' calibration files written first). The exit status if they cannot be had.
std::optional<int> LoadSetup(const MonocledOptions& o, monocle::ServiceSetup* out) {
  monocle::Result<monocle::ServiceSetup> setup = monocle::MakeError(monocle::ErrorCode::kIo, "");
  if (!o.replay_path.empty()) {
    setup = monocle::ReplaySetup(o.replay_path, o.state_dir, o.replay_pace);
  } else if (o.config_path.empty()) {
    if (auto s = monocle::EnsureSimulatorCalibrations(o.state_dir); !s) {
      std::cerr << "monocled: error: " << s.error() << "\n";
      return 1;
    }
    setup = monocle::ParseServiceConfig(monocle::EmbeddedDefaultConfig(), "embedded default",
                                        o.state_dir);
  } else {
    setup = monocle::LoadServiceConfig(o.config_path);
  }
  if (!setup) {
    std::cerr << "monocled: error: " << setup.error() << "\n";
    return 2;
  }
  if (o.domain) setup->domain = *o.domain;
  if (!o.security_dir.empty()) {
    if (auto c = monocle::dds::CheckSecurityDirectory(o.security_dir); !c) {
      std::cerr << "monocled: error: --security: " << c.error() << "\n";
      return 2;
    }
    setup->security_dir = o.security_dir;
  }
  if (!setup->security_dir.empty() && setup->domain > 230)
    return Usage("a secured domain must be 0..230 (DDS Security governance)");
  if (!o.record_path.empty() && o.record_options.frames_every > 0) {
    // The recorder is an in-process subscriber of image_raw: let every frame through.
    for (auto& cam : setup->cameras) cam.image_max_rate_hz = 1000;
  }
  *out = std::move(*setup);
  return std::nullopt;
}

void LogServing(const monocle::Service& service, const monocle::ServiceSetup& setup) {
  // Refused cameras were logged by Start with the reason; these are the ones served.
  for (const auto& cam : service.served_cameras()) {
    std::cerr << "monocled: camera '" << cam.id << "' (" << cam.options.device << ", "
              << monocle::ToString(cam.role) << ", calibration "
              << (cam.calibration_path.empty() ? "from camera_info" : cam.calibration_path)
              << "; ROS 2 " << cam.ros_namespace << "/{"
              << (cam.corner() ? "corner_pose,pose,get_pose," : "")
              << (cam.room_map ? "map_pose," : "")
              << (cam.floor() ? "measure_points,calibrate_floor," : "")
              << "camera_info,image_raw}, frame " << cam.ros_frame
              << (cam.room_map
                      ? "; room map " + cam.room_map_path + ", tf map -> " + cam.mount->base_frame
                      : "")
              << ")\n";
  }
  std::cerr << "monocled: serving on DDS domain " << setup.domain << " as " << service.id()
            << " (ROS 2: ROS_DOMAIN_ID=" << setup.domain
            << ", also /tf, /diagnostics, /monocle/cameras, /monocle/calibrations)"
            << (setup.security_dir.empty() ? ", plain DDS (no security_dir)"
                                           : ", DDS Security as " + setup.security_dir)
            << "\n";
}

// Publishes the status every period until a stop signal; a recording that fails ends alone.
void ServeUntilStopped(monocle::Service& service, const monocle::ServiceSetup& setup,
                       const sigset_t& stop_signals, const std::string& record_path,
                       std::unique_ptr<monocle::record::Recorder>& recorder) {
  const auto period = setup.status_period;
  timespec wait{static_cast<time_t>(period.count() / 1000),
                static_cast<long>(period.count() % 1000) * 1000000L};
  while (true) {
    const int signal = sigtimedwait(&stop_signals, nullptr, &wait);
    if (signal == SIGINT || signal == SIGTERM) break;
    service.PublishStatus();
    // Free pages inside the heaps (between live blocks, which the trim threshold in main
    // does not reach) go back to the system once a period.
    malloc_trim(0);
    if (recorder && recorder->error()) {
      // The service goes on; only the recording ends (its file is closed with its index).
      std::cerr << "monocled: " << recorder->error()->message << "; " << record_path
                << " holds everything before it\n";
      (void)recorder->Finish();
      recorder.reset();
    }
  }
  if (recorder) {
    const monocle::Status closed = recorder->Finish();
    std::cerr << "monocled: recording " << record_path
              << (closed ? " closed" : " ended with an error: " + closed.error().message) << "\n";
    recorder.reset();
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Stop signals are waited for, never delivered: blocked before anything else (every thread
  // started later inherits the mask), so one that comes while the configuration is read or
  // the service starts stays pending and is obeyed at the next step (StopRequested).
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  // Every frame's working images are a megabyte or more: keep them in the heap for reuse
  // instead of mmap'ing and unmapping them per frame (page faults on every frame). Up to
  // 16 MB free at the top of each thread's heap stays for the next frame; more goes back
  // (glibc's malloc_trim never shrinks a thread's heap: start-up's rendering left 25 MB).
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 16 << 20);
  MonocledOptions options;
  if (const auto exit_status = ParseOptions(argc, argv, &options)) return *exit_status;
  if (options.print_config) return PrintConfig(options);
  monocle::ServiceSetup setup;
  if (const auto exit_status = LoadSetup(options, &setup)) return *exit_status;
  // A file size limit must end the recording with its summary, not the service.
  std::signal(SIGXFSZ, SIG_IGN);

  // The recorder starts before the cameras, so the recording holds every frame processed.
  std::unique_ptr<monocle::record::Recorder> recorder;
  auto start_recording = [&](monocle::Service& started) -> monocle::Status {
    if (options.record_path.empty()) return monocle::Ok{};
    for (const auto& cam : started.served_cameras())
      options.record_options.namespaces.push_back(cam.ros_namespace);
    auto recording = monocle::record::Recorder::Start(started.participant(), options.record_path,
                                                      options.record_options);
    if (!recording) {
      return monocle::MakeError(recording.error().code, "--record: " + recording.error().message);
    }
    recorder = std::move(*recording);
    std::cerr << "monocled: recording to " << options.record_path << "\n";
    return monocle::Ok{};
  };
  auto service = monocle::Service::Start(setup, StopRequested, start_recording);
  if (!service && service.error().code == monocle::ErrorCode::kCancelled) {
    std::cerr << "monocled: stopped during start-up\n";
    return 0;
  }
  if (!service) {
    std::cerr << "monocled: error: " << service.error() << "\n";
    return 1;
  }
  LogServing(**service, setup);
  ServeUntilStopped(**service, setup, stop_signals, options.record_path, recorder);
  (*service)->Stop();
  std::cerr << "monocled: stopped\n";
  return 0;
}
