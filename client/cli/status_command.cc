// monocle status: the service's cameras, as its status topic says.
#include <csignal>
#include <iomanip>
#include <iostream>
#include <thread>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/live.h"
#include "client/cli/shared_options.h"

namespace monocle::cli {
namespace {

constexpr const char* kStatusAbout =
    R"(Every camera of every monocled on the DDS domain (topic /monocle/cameras): its ROS namespace
(where its topics and services are; name a camera by it when several robots share a domain),
role, state (streaming, reconnecting, stopped), frames per second, frames received, dropped
(sent by the camera, never received), skipped (not processed because processing was busy),
processing latency (frame received -> result published, median over the status period, ms),
and the last error (with --json also the DDS participant each status came from, which tells
apart two services giving one service id). Exit status 1 when a camera has failed (a
configuration error, e.g. a device that is no camera: it is not retried) or stopped (a
replayed recording ended), or two monocled serve the same namespace: the container's
healthcheck.)";

proto::StatusOutput ToOutput(const CameraStatus& s) {
  proto::StatusOutput out;
  out.set_camera(s.camera_id);
  out.set_device(s.device);
  out.set_role(s.role);
  out.set_state(ToString(s.state));
  out.set_fps(s.fps);
  out.set_frames(s.frames);
  out.set_dropped(s.dropped);
  out.set_skipped(s.skipped);
  out.set_latency_ms(s.latency_ms);
  out.set_last_error(s.last_error);
  out.set_last_error_ns(s.last_error_ns);
  out.set_stamp_ns(s.stamp_ns);
  out.set_ros_namespace(s.ros_namespace);
  out.set_service(s.service);
  out.set_participant(s.participant);
  return out;
}

void PrintHeader() {
  std::cout << std::left << std::setw(14) << "CAMERA" << std::setw(24) << "NAMESPACE"
            << std::setw(14) << "ROLE" << std::setw(14) << "STATE" << std::right << std::setw(7)
            << "FPS" << std::setw(10) << "FRAMES" << std::setw(9) << "DROPPED" << std::setw(9)
            << "SKIPPED" << std::setw(12) << "LATENCY ms"
            << "  LAST ERROR\n";
}

void Print(const CameraStatus& s, bool json) {
  if (json) {
    std::cout << ToJson(ToOutput(s)) << std::endl;
    return;
  }
  std::cout << std::left << std::setw(14) << s.camera_id << std::setw(24) << s.ros_namespace
            << std::setw(14) << s.role << std::setw(14) << ToString(s.state) << std::right
            << std::fixed << std::setprecision(1) << std::setw(7) << s.fps << std::setw(10)
            << s.frames << std::setw(9) << s.dropped << std::setw(9) << s.skipped << std::setw(12)
            << std::setprecision(2) << s.latency_ms << "  " << s.last_error << std::endl;
}

}  // namespace

int StatusCommand(const std::vector<std::string>& argv) {
  LiveOptions live;
  bool watch = false, json = false;
  CommandLine line("status", kStatusAbout);
  line.Flag("--watch", &watch, "keep printing every update until Ctrl-C");
  line.Flag("--json", &json, "one JSON object per camera per line");
  DeclareServiceOptions(line, &live, "give up after S seconds without an answer");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  // With --watch, Ctrl-C ends it cleanly: the signal is waited for below, so block it before
  // any thread (DDS's included) starts and would take it instead.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  if (watch) pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  int exit_status = kExitOk;
  auto client = OpenClient(live, &exit_status);
  if (!client) return exit_status;
  const auto current = client->status();
  if (!current) return Fail(current.error());
  if (!json) PrintHeader();
  for (const auto& s : *current) Print(s, json);
  if (const std::string clash = DuplicateCameras(*current); !clash.empty()) {
    std::cerr << "monocle: warning: " << clash
              << ": their topics and requests mix; give each robot its own ros_namespace "
                 "(service/README.md, \"Several robots on one domain\")\n";
    exit_status = kExitFailure;
  }
  // A camera that failed for good (a configuration error) or stopped (it sends nothing until
  // the service restarts) makes the service unhealthy: the container's healthcheck runs this.
  for (const auto& s : *current) {
    if (s.state == CameraState::kFailed) {
      std::cerr << "monocle: error: camera '" << s.camera_id << "' failed: " << s.last_error
                << "\n";
      exit_status = kExitFailure;
    } else if (s.state == CameraState::kStopped) {
      std::cerr << "monocle: error: camera '" << s.camera_id << "' is stopped"
                << (s.last_error.empty() ? "" : ": " + s.last_error) << "\n";
      exit_status = kExitFailure;
    }
  }
  if (!watch) return exit_status;

  // Until Ctrl-C: updates arrive on the subscription's thread; this one waits for the signal.
  std::mutex print;
  auto sub = client->subscribe_status([&](const CameraStatus& s) {
    std::lock_guard<std::mutex> lock(print);
    Print(s, json);
  });
  if (!sub) return Fail(sub.error());
  int signal = 0;
  sigwait(&stop, &signal);
  return kExitOk;
}

}  // namespace monocle::cli
