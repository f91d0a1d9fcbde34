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
#include "service/server/point_queries.h"
#include "service/server/pose_messages.h"

#include <deque>
#include <map>

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
  --floor-camera ID      answers point queries (topics monocle/point_request and
                         monocle/point_reply) for this floor camera (default sim-floor)
  --floor-calibration F  its calibration file, with a floor section (for sim-floor the
                         simulator's own calibration is used when none is given)

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
  std::string camera = "sim-corner", calibration_path, floor_camera = "sim-floor",
              floor_calibration_path;
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
    } else if (a == "--floor-camera") {
      floor_camera = value();
    } else if (a == "--floor-calibration") {
      floor_calibration_path = value();
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
      /*reader=*/false, monocle::dds::EndpointQos{1, false});
  if (!endpoint) {
    std::cerr << "monocled: error: " << endpoint.error() << "\n";
    return 1;
  }

  // Point queries: need only the floor camera's calibration.
  std::map<std::string, monocle::CameraCalibration> floor_cameras;
  if (!floor_calibration_path.empty()) {
    auto cal = monocle::LoadCalibrationFile(floor_calibration_path);
    if (!cal) {
      std::cerr << "monocled: error: " << cal.error() << "\n";
      return 1;
    }
    if (!cal->floor) {
      std::cerr << "monocled: error: " << floor_calibration_path << " has no floor section\n";
      return 1;
    }
    floor_cameras[floor_camera] = *cal;
  } else if (floor_camera == "sim-floor") {
    monocle::CameraCalibration cal;
    cal.intrinsics = monocle::SimIntrinsics(1280, 1024);
    cal.floor = monocle::FloorCalibration{};
    cal.floor->pose = monocle::SimFloorPose();
    floor_cameras[floor_camera] = cal;
  }
  auto requests = monocle::dds::Endpoint<monocle_dds_PointRequest>::Open(
      domain, &monocle_dds_PointRequest_desc, monocle::dds::kPointRequestTopic, false, true,
      monocle::dds::EndpointQos{64, false});
  auto replies = monocle::dds::Endpoint<monocle_dds_PointReply>::Open(
      domain, &monocle_dds_PointReply_desc, monocle::dds::kPointReplyTopic, true, false,
      monocle::dds::EndpointQos{1, true});
  if (!requests || !replies) {
    std::cerr << "monocled: error: " << (!requests ? requests.error() : replies.error()) << "\n";
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
  struct Request {
    std::string client_id, camera_id;
    uint64_t request_id = 0;
    double sigma = 0;
    std::vector<monocle::PixelPair> points;
  };
  std::thread queries([&] {
    std::deque<std::pair<std::string, uint64_t>> answered;  // replies kept for late readers
    while (true) {
      {
        std::lock_guard<std::mutex> lock(latest.mutex);
        if (latest.stop) return;
      }
      auto taken = requests->Take<Request>(
          std::chrono::milliseconds(200), [](const monocle_dds_PointRequest& r) {
            Request out{r.client_id != nullptr ? r.client_id : "",
                        r.camera_id != nullptr ? r.camera_id : "",
                        r.request_id,
                        r.pixel_sigma_px,
                        {}};
            out.points.reserve(r.points._length);
            for (uint32_t i = 0; i < r.points._length; ++i) {
              const auto& q = r.points._buffer[i];
              out.points.push_back({q.u, q.v, q.paired, q.floor_u, q.floor_v});
            }
            return out;
          });
      if (!taken) continue;
      for (const auto& r : *taken) {
        const auto answer =
            monocle::AnswerPointRequest(floor_cameras, r.camera_id, r.points, r.sigma);
        std::vector<monocle_dds_PointResult> results(answer.points.size());
        for (size_t i = 0; i < answer.points.size(); ++i) {
          const auto& a = answer.points[i];
          auto& out = results[i];
          out.status = static_cast<uint8_t>(a.status);
          const auto sigma = a.measurement.Sigma();
          out.x = a.measurement.p_robot_m.x();
          out.y = a.measurement.p_robot_m.y();
          out.z = a.measurement.p_robot_m.z();
          for (int c = 0; c < 3; ++c) out.sigma[c] = sigma[c];
          out.error = const_cast<char*>(a.error.c_str());
        }
        monocle_dds_PointReply reply{};
        reply.client_id = const_cast<char*>(r.client_id.c_str());
        reply.request_id = r.request_id;
        reply.status = static_cast<uint8_t>(answer.status);
        reply.error = const_cast<char*>(answer.error.c_str());
        reply.points._buffer = results.data();
        reply.points._length = reply.points._maximum = static_cast<uint32_t>(results.size());
        reply.points._release = false;
        if (auto s = replies->Write(reply); !s) std::cerr << "monocled: " << s.error() << "\n";
        answered.emplace_back(r.client_id, r.request_id);
        // Kept replies reach a client whose reader matched late; forget old ones.
        if (answered.size() > 64) {
          monocle_dds_PointReply key{};
          key.client_id = const_cast<char*>(answered.front().first.c_str());
          key.request_id = answered.front().second;
          replies->Unregister(key);
          answered.pop_front();
        }
      }
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
  queries.join();
  std::cerr << "monocled: stopped (" << latest.replaced
            << " frames skipped while processing was busy)\n";
  return 0;
}
