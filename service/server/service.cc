#include "service/server/service.h"

#include <unistd.h>

#include <iostream>

#include "camera/ros/ros_topic_source.h"
#include "service/server/wire_values.h"

namespace monocle {
namespace {

int64_t UnixNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string ThisServiceId() {
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  return std::string(host) + "/" + std::to_string(::getpid());
}

}  // namespace

Result<std::unique_ptr<Service>> Service::Start(
    const ServiceSetup& setup, const std::function<bool()>& stop_requested,
    const std::function<Status(Service&)>& before_cameras) {
  const Error cancelled = MakeError(ErrorCode::kCancelled, "start-up stopped by a signal");
  std::unique_ptr<Service> s(new Service());
  s->setup_ = setup;
  s->service_id_ = ThisServiceId();
  std::map<std::string, CameraCalibration> loaded;
  for (const auto& cam : s->setup_.cameras) {
    if (stop_requested()) return cancelled;
    if (cam.calibration_path.empty()) {  // intrinsics from the image topic's camera_info
      CameraCalibration from_camera_info;
      from_camera_info.ceiling_distance_m = cam.ceiling_distance_m;
      loaded[cam.id] = from_camera_info;
      s->calibrations_.Add(cam.id, from_camera_info);
      continue;
    }
    // A floor calibration killed half-way left its temporary: gone before we write again.
    if (const int stale = RemoveStaleTemporaries(cam.calibration_path); stale > 0) {
      std::cerr << "monocled: removed " << stale << " stale temporary file(s) next to "
                << cam.calibration_path << " (a write that was killed)\n";
    }
    auto cal = LoadCalibrationFile(cam.calibration_path);
    if (!cal) return MakeError(cal.error().code, "camera '" + cam.id + "': " + cal.error().message);
    if (cam.corner() && !cam.ceiling_distance_m && !cal->ceiling_distance_m) {
      return MakeError(ErrorCode::kInvalidArgument,
                       "camera '" + cam.id + "' has the corner role but no ceiling distance: add " +
                           "corner { ceiling_distance: Z } to " + cam.calibration_path +
                           " or ceiling_distance_m to its camera { } in the configuration");
    }
    loaded[cam.id] = *cal;
    s->calibrations_.Add(cam.id, *cal);
  }

  if (stop_requested()) return cancelled;
  auto participant =
      dds::CreateParticipant(s->setup_.domain, s->setup_.security_dir, wire::kMaxSampleBytes);
  if (!participant) return participant.error();
  s->participant_ = *participant;
  const auto& p = s->participant_;

  // A camera namespace another monocled already serves is refused here, before anything of
  // it is opened: its requests and topics stay the other service's alone.
  std::vector<std::string> namespaces;
  for (const auto& cam : s->setup_.cameras) namespaces.push_back(cam.ros_namespace);
  auto duplicates = DuplicateWatch::Open(p, s->service_id_, namespaces);
  if (!duplicates) return duplicates.error();
  s->duplicates_ = std::move(duplicates).value();
  const auto served = s->duplicates_->WaitForServed(s->setup_.discovery_wait, stop_requested);
  if (stop_requested()) return cancelled;
  for (auto it = s->setup_.cameras.begin(); it != s->setup_.cameras.end();) {
    const auto other = served.find(it->ros_namespace);
    if (other == served.end()) {
      ++it;
      continue;
    }
    WorkerStatus refusal;
    refusal.state = SourceState::kFailed;
    refusal.last_error = "not served: camera namespace " + it->ros_namespace +
                         " is already served by monocled " + other->second +
                         " on this DDS domain; give this camera its own ros_namespace";
    refusal.last_error_ns = UnixNowNs();
    std::cerr << "monocled: camera '" << it->id << "' " << refusal.last_error << "\n";
    s->refused_.push_back({*it, refusal});
    it = s->setup_.cameras.erase(it);
  }
  const auto& cameras = s->setup_.cameras;
  std::vector<CameraSetup> status_only;
  for (const auto& r : s->refused_) status_only.push_back(r.camera);

  auto topics = RosTopics::Open(p, cameras, status_only);
  if (!topics) return topics.error();
  s->topics_ = std::move(topics).value();

  if (stop_requested()) return cancelled;
  Service* self = s.get();
  auto points = PointQueryHandler::Start(p, cameras, s->calibrations_);
  if (!points) return points.error();
  s->point_queries_ = std::move(points).value();
  auto poses = PoseQueryHandler::Start(p, cameras);
  if (!poses) return poses.error();
  s->pose_queries_ = std::move(poses).value();
  auto floor = FloorCalibrationHandler::Start(
      p, cameras, s->calibrations_, [self](const std::string& id) { return self->Find(id); },
      [self](const CameraSetup& cam, const CameraCalibration& cal, uint64_t revision) {
        self->PublishCalibration(cam, cal, revision);
      });
  if (!floor) return floor.error();
  s->floor_calibration_ = std::move(floor).value();
  // Every ROS endpoint exists now: name them in ROS 2's graph.
  // Not worth failing the service for: a keystore made before monocle published it does
  // not permit the topic.
  if (s->setup_.ros_discovery != RosDiscoveryLayout::kOff) {
    auto graph = RosDiscoveryInfo::Publish(p, s->setup_.ros_discovery);
    if (graph) {
      s->ros_discovery_ = std::move(graph).value();
    } else {
      std::cerr << "monocled: warning: " << graph.error().message
                << ": `ros2 node list` will not show monocled (with DDS Security, make the "
                   "keystore again with monocle security init; or set ros_discovery_info: "
                   "\"off\")\n";
    }
  }

  for (const auto& cam : cameras) {
    CameraWorker::OpenSource open_source;
    if (IsRosTopicDevice(cam.options.device)) {
      open_source = [p, &cam](CameraWorker::StateCallback on_state) {
        auto source =
            RosTopicSource::Open(p, cam.options.device, std::move(on_state), cam.stall_timeout);
        if (!source) return Result<std::unique_ptr<FrameSource>>(source.error());
        return Result<std::unique_ptr<FrameSource>>(std::move(source).value());
      };
    }
    self->workers_.push_back(std::make_unique<CameraWorker>(
        cam, loaded[cam.id], [self, &cam](const ProcessedFrame& f) { self->OnProcessed(cam, f); },
        [self, id = cam.id] {
          if (auto* w = self->Find(id)) self->PublishStatusOf(*w, false);
        },
        [self, &cam](const Frame& frame) { self->topics_->PublishImage(cam, frame); },
        std::move(open_source),
        [self, &cam](const CameraCalibration& cal) {
          self->calibrations_.Add(cam.id, cal);
          self->PublishCalibration(cam, cal, 1);
        }));
  }
  if (stop_requested()) return cancelled;
  for (const auto& cam : cameras) {
    if (HasIntrinsics(loaded[cam.id])) s->PublishCalibration(cam, loaded[cam.id], 1);
  }
  if (before_cameras) {
    if (Status ready = before_cameras(*s); !ready) return ready.error();
  }
  for (auto& w : s->workers_) {
    if (stop_requested()) return cancelled;  // ~Service stops the workers already started
    w->Start();
  }
  s->PublishStatus();
  return s;
}

Service::~Service() { Stop(); }

void Service::Stop() {
  if (stop_.exchange(true)) return;
  // Cameras first: their callbacks use the handlers and topics.
  for (auto& w : workers_) w->Stop();
  point_queries_.reset();
  pose_queries_.reset();
  floor_calibration_.reset();
  for (auto& w : workers_) PublishStatusOf(*w, false);
  // A refused camera was never ours: its last word is "stopped" too, so nobody waits on it.
  for (auto& r : refused_) {
    if (!topics_) break;  // start-up was stopped before the topics were opened
    r.status.state = SourceState::kStopped;
    topics_->PublishStatus(r.camera, CameraStatusOf(r.camera, r.status, service_id_, UnixNowNs()));
  }
}

CameraWorker* Service::Find(const std::string& camera_id) {
  for (auto& w : workers_) {
    if (w->setup().id == camera_id) return w.get();
  }
  return nullptr;
}

void Service::OnProcessed(const CameraSetup& camera, const ProcessedFrame& frame) {
  topics_->PublishPose(camera, frame);
  if (pose_queries_) pose_queries_->OnPose(PoseOf(camera, frame));
}

void Service::PublishStatus() {
  for (auto& clash : duplicates_->NewClashes()) {
    std::cerr << "monocled: " << clash.message << "\n";
    std::lock_guard<std::mutex> lock(notes_mutex_);
    notes_[clash.ros_namespace] = {std::move(clash.message), UnixNowNs()};
  }
  for (const std::string& ns : duplicates_->ClashesOver()) {
    std::cerr << "monocled: camera namespace " << ns
              << " is ours alone again: the other service claiming it has left\n";
    std::lock_guard<std::mutex> lock(notes_mutex_);
    notes_.erase(ns);
  }
  std::vector<std::pair<const CameraSetup*, WorkerStatus>> statuses;
  for (auto& w : workers_) statuses.emplace_back(&w->setup(), PublishStatusOf(*w, true));
  const int64_t now_ns = UnixNowNs();
  for (const auto& r : refused_) {
    topics_->PublishStatus(r.camera, CameraStatusOf(r.camera, r.status, service_id_, now_ns));
    statuses.emplace_back(&r.camera, r.status);
  }
  topics_->PublishDiagnostics(statuses, now_ns);
  {
    std::lock_guard<std::mutex> lock(intrinsics_mutex_);
    for (auto& w : workers_) {
      if (const auto it = intrinsics_.find(w->setup().id); it != intrinsics_.end())
        topics_->PublishCameraInfo(w->setup(), it->second, now_ns);
    }
  }
}

WorkerStatus Service::PublishStatusOf(CameraWorker& worker, bool new_period) {
  WorkerStatus st = worker.Snapshot(new_period);
  {
    // Another service on this camera's namespace: said in its status until a newer error.
    std::lock_guard<std::mutex> lock(notes_mutex_);
    const auto note = notes_.find(worker.setup().ros_namespace);
    if (note != notes_.end() && note->second.second >= st.last_error_ns) {
      st.last_error = note->second.first;
      st.last_error_ns = note->second.second;
    }
  }
  topics_->PublishStatus(worker.setup(),
                         CameraStatusOf(worker.setup(), st, service_id_, UnixNowNs()));
  return st;
}

void Service::PublishCalibration(const CameraSetup& camera, const CameraCalibration& cal,
                                 uint64_t revision) {
  {
    std::lock_guard<std::mutex> lock(intrinsics_mutex_);
    intrinsics_[camera.id] = cal.intrinsics;
  }
  topics_->PublishCalibration(camera, CalibrationOf(camera, cal, revision, UnixNowNs()));
}

}  // namespace monocle
