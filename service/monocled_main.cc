// monocled: the measurement service. This first version streams corner poses over DDS
// (topic monocle/pose) from one camera; point queries, calibration commands, status and
// the configuration file follow (see README).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "camera/aravis/aravis_source.h"
#include "camera/sim/sim_gv_camera.h"
#include "service/io/calibration_file.h"
#include "service/server/dds.h"
#include "service/server/pose_messages.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: monocled [--camera ID] [--calibration CAL.pbtxt] [--ceiling-distance Z] [--domain D]

Streams the camera's pose from a ceiling corner over DDS, topic monocle/pose, one sample
per processed frame (the corner frame and units of `monocle corner locate`).

  --camera ID            Aravis id, IP address or serial, or the built-in simulated
                         camera sim-corner (default)
  --calibration CAL      intrinsics and corner { ceiling_distance } (not needed for
                         sim-corner)
  --ceiling-distance Z   camera to ceiling, metres (overrides the file)
  --domain D             DDS domain id (default 0); CYCLONEDDS_URI configures Cyclone DDS

SIGINT or SIGTERM stop it cleanly.
)";

struct LatestFrame {
  std::mutex mutex;
  std::condition_variable ready;
  std::optional<monocle::Frame> frame;
  uint64_t replaced = 0;  // frames dropped because processing was still busy
  bool stop = false;
};

}  // namespace

int main(int argc, char** argv) {
  std::string camera = "sim-corner", calibration_path;
  std::optional<double> ceiling;
  int domain = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "monocled: error: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (a == "--camera") {
      camera = value();
    } else if (a == "--calibration") {
      calibration_path = value();
    } else if (a == "--ceiling-distance") {
      ceiling = std::atof(value().c_str());
    } else if (a == "--domain") {
      domain = std::atoi(value().c_str());
    } else {
      std::cerr << "monocled: error: unknown option " << a << " (see --help)\n";
      return 2;
    }
  }

  // Stop signals are waited for by the main thread; every other thread inherits the mask.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  monocle::AravisOptions options;
  options.device = camera;
  auto source = monocle::AravisSource::Open(options);
  if (!source) {
    std::cerr << "monocled: error: " << source.error() << "\n";
    return 1;
  }
  monocle::CameraIntrinsics intrinsics;
  double zc = ceiling.value_or(0);
  if (const auto* sim = (*source)->SimulatedScenes()) {
    intrinsics = sim->intrinsics();
    if (!ceiling) zc = sim->trajectory().front().z_m;
  } else {
    if (calibration_path.empty()) {
      std::cerr << "monocled: error: --calibration CAL.pbtxt is needed for camera '" << camera
                << "'\n";
      return 2;
    }
    auto cal = monocle::LoadCalibrationFile(calibration_path);
    if (!cal) {
      std::cerr << "monocled: error: " << cal.error() << "\n";
      return 1;
    }
    intrinsics = cal->intrinsics;
    if (!ceiling && cal->ceiling_distance_m) zc = *cal->ceiling_distance_m;
  }
  if (!(zc > 0)) {
    std::cerr << "monocled: error: the ceiling distance is unknown: --ceiling-distance Z\n";
    return 2;
  }
  auto endpoint = monocle::dds::Endpoint<monocle_dds_CornerPose>::Open(
      domain, &monocle_dds_CornerPose_desc, monocle::dds::kPoseTopic, /*writer=*/true,
      /*reader=*/false,
      /*keep_last_per_key=*/true);
  if (!endpoint) {
    std::cerr << "monocled: error: " << endpoint.error() << "\n";
    return 1;
  }

  LatestFrame latest;
  // Acquisition: never waits for processing; a newer frame replaces one not yet taken.
  std::thread acquisition([&] {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(latest.mutex);
        if (latest.stop) return;
      }
      auto frame = (*source)->Next(std::chrono::milliseconds(500));
      if (!frame) continue;
      // Processing may hold a frame for longer than the ring has buffers: copy out of it.
      frame->grey = frame->grey.clone();
      frame->keepalive.reset();
      std::lock_guard<std::mutex> lock(latest.mutex);
      if (latest.frame) ++latest.replaced;
      latest.frame = std::move(*frame);
      latest.ready.notify_one();
    }
  });
  std::thread processing([&] {
    while (true) {
      monocle::Frame frame;
      {
        std::unique_lock<std::mutex> lock(latest.mutex);
        latest.ready.wait(lock, [&] { return latest.stop || latest.frame.has_value(); });
        if (latest.stop) return;
        frame = std::move(*latest.frame);
        latest.frame.reset();
      }
      const auto start = std::chrono::steady_clock::now();
      const auto pose = monocle::LocateCorner(frame.grey, intrinsics, zc);
      const int64_t processing_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now() - start)
                                        .count();
      monocle_dds_CornerPose sample;
      std::string error;
      monocle::dds::ToSample(camera, frame.sequence, frame.capture_time_ns,
                             frame.time_source == monocle::TimeSource::kCamera, pose, processing_ns,
                             &sample, &error);
      if (auto s = endpoint->Write(sample); !s) std::cerr << "monocled: " << s.error() << "\n";
    }
  });
  std::cerr << "monocled: streaming poses of camera '" << camera << "' on DDS domain " << domain
            << ", topic " << monocle::dds::kPoseTopic << "\n";
  int signal = 0;
  sigwait(&stop_signals, &signal);
  {
    std::lock_guard<std::mutex> lock(latest.mutex);
    latest.stop = true;
    latest.ready.notify_all();
  }
  acquisition.join();
  processing.join();
  std::cerr << "monocled: stopped (" << latest.replaced
            << " frames skipped while processing was busy)\n";
  return 0;
}
