#include "service/server/service.h"

#include <cstring>
#include <iostream>

#include "service/server/point_queries.h"
#include "service/server/pose_messages.h"
#include "service/vision/floor_calibrator.h"

namespace monocle {
namespace {

using std::chrono::milliseconds;

// How long a "pose of the next frame" request or a floor calibration command waits for the
// camera's next frame.
constexpr milliseconds kFrameWait{5000};
// Request handlers wake this often to notice a stop.
constexpr milliseconds kPoll{200};

int64_t UnixNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string Text(const char* s) { return s != nullptr ? s : ""; }
char* Chars(const std::string& s) { return const_cast<char*>(s.c_str()); }

template <typename T>
Result<std::unique_ptr<dds::Endpoint<T>>> OpenEndpoint(const std::shared_ptr<dds::Entity>& p,
                                                       const dds_topic_descriptor_t* type,
                                                       const char* topic, bool writer, bool reader,
                                                       dds::EndpointQos qos) {
  auto ep = dds::Endpoint<T>::Open(p, type, topic, writer, reader, qos);
  if (!ep) return ep.error();
  return std::make_unique<dds::Endpoint<T>>(std::move(ep).value());
}

struct PointRequest {
  std::string client_id, camera_id;
  uint64_t request_id = 0;
  double sigma = 0;
  std::vector<PixelPair> points;
};

struct PoseRequest {
  std::string client_id, camera_id;
  uint64_t request_id = 0;
  uint8_t which = 0;
};

struct FloorRequest {
  std::string client_id, camera_id;
  uint64_t request_id = 0;
  int cols = 0, rows = 0;
  double square_m = 0;
};

}  // namespace

Result<std::unique_ptr<Service>> Service::Start(const ServiceSetup& setup) {
  std::unique_ptr<Service> s(new Service());
  s->setup_ = setup;
  std::map<std::string, CameraCalibration> calibrations;
  for (const auto& cam : setup.cameras) {
    auto cal = LoadCalibrationFile(cam.calibration_path);
    if (!cal) return MakeError(cal.error().code, "camera '" + cam.id + "': " + cal.error().message);
    if (cam.corner() && !cam.ceiling_distance_m && !cal->ceiling_distance_m) {
      return MakeError(ErrorCode::kInvalidArgument,
                       "camera '" + cam.id + "' has the corner role but no ceiling distance: add " +
                           "corner { ceiling_distance: Z } to " + cam.calibration_path +
                           " or ceiling_distance_m to its camera { } in the configuration");
    }
    calibrations[cam.id] = *cal;
    if (cam.floor()) s->floor_calibrations_[cam.id] = *cal;
    s->revisions_[cam.id] = 1;
  }

  auto participant = dds::CreateParticipant(setup.domain);
  if (!participant) return participant.error();
  s->participant_ = *participant;
  const auto& p = s->participant_;
  auto poses = OpenEndpoint<monocle_dds_CornerPose>(p, &monocle_dds_CornerPose_desc,
                                                    dds::kPoseTopic, true, false, {1, false});
  if (!poses) return poses.error();
  s->poses_ = std::move(poses).value();
  auto cals = OpenEndpoint<monocle_dds_Calibration>(p, &monocle_dds_Calibration_desc,
                                                    dds::kCalibrationTopic, true, false, {1, true});
  if (!cals) return cals.error();
  s->calibrations_ = std::move(cals).value();
  auto status = OpenEndpoint<monocle_dds_CameraStatus>(p, &monocle_dds_CameraStatus_desc,
                                                       dds::kStatusTopic, true, false, {1, true});
  if (!status) return status.error();
  s->status_ = std::move(status).value();

  auto point_req = OpenEndpoint<monocle_dds_PointRequest>(
      p, &monocle_dds_PointRequest_desc, dds::kPointRequestTopic, false, true, dds::kRequestQos);
  auto point_rep = dds::Endpoint<monocle_dds_PointReply>::Open(
      p, &monocle_dds_PointReply_desc, dds::kPointReplyTopic, true, false, dds::kReplyQos);
  auto pose_req = OpenEndpoint<monocle_dds_PoseRequest>(
      p, &monocle_dds_PoseRequest_desc, dds::kPoseRequestTopic, false, true, dds::kRequestQos);
  auto pose_rep = dds::Endpoint<monocle_dds_PoseReply>::Open(
      p, &monocle_dds_PoseReply_desc, dds::kPoseReplyTopic, true, false, dds::kReplyQos);
  auto floor_req = OpenEndpoint<monocle_dds_FloorCalibrationRequest>(
      p, &monocle_dds_FloorCalibrationRequest_desc, dds::kFloorCalibrationRequestTopic, false, true,
      dds::kRequestQos);
  auto floor_rep = dds::Endpoint<monocle_dds_FloorCalibrationReply>::Open(
      p, &monocle_dds_FloorCalibrationReply_desc, dds::kFloorCalibrationReplyTopic, true, false,
      dds::kReplyQos);
  for (const Error* e :
       {point_req ? nullptr : &point_req.error(), point_rep ? nullptr : &point_rep.error(),
        pose_req ? nullptr : &pose_req.error(), pose_rep ? nullptr : &pose_rep.error(),
        floor_req ? nullptr : &floor_req.error(), floor_rep ? nullptr : &floor_rep.error()}) {
    if (e != nullptr) return *e;
  }
  s->point_requests_ = std::move(point_req).value();
  s->point_replies_ =
      std::make_unique<dds::ReplyPublisher<monocle_dds_PointReply>>(std::move(point_rep).value());
  s->pose_requests_ = std::move(pose_req).value();
  s->pose_replies_ =
      std::make_unique<dds::ReplyPublisher<monocle_dds_PoseReply>>(std::move(pose_rep).value());
  s->floor_requests_ = std::move(floor_req).value();
  s->floor_replies_ = std::make_unique<dds::ReplyPublisher<monocle_dds_FloorCalibrationReply>>(
      std::move(floor_rep).value());

  auto ros = RosTopics::Open(p, setup.cameras);
  if (!ros) return ros.error();
  s->ros_ = std::move(ros).value();

  Service* self = s.get();
  for (const auto& cam : setup.cameras) {
    self->workers_.push_back(std::make_unique<CameraWorker>(
        cam, calibrations[cam.id],
        [self, id = cam.id](const ProcessedFrame& f) { self->OnProcessed(id, f); },
        [self, id = cam.id] {
          if (auto* w = self->Find(id)) self->PublishStatusOf(*w, false);
        },
        [self, cam](const Frame& frame) { self->ros_->PublishImage(cam, frame); }));
  }
  for (const auto& cam : setup.cameras) s->PublishCalibration(cam.id, calibrations[cam.id]);
  for (auto& w : s->workers_) w->Start();
  s->point_thread_ = std::thread([self] { self->ServePointRequests(); });
  s->pose_thread_ = std::thread([self] { self->ServePoseRequests(); });
  s->floor_thread_ = std::thread([self] { self->ServeFloorCalibrationRequests(); });
  s->PublishStatus();
  return s;
}

Service::~Service() { Stop(); }

void Service::Stop() {
  if (stop_.exchange(true)) return;
  for (auto* t : {&point_thread_, &pose_thread_, &floor_thread_}) {
    if (t->joinable()) t->join();
  }
  for (auto& w : workers_) w->Stop();
  for (auto& w : workers_) PublishStatusOf(*w, false);
}

CameraWorker* Service::Find(const std::string& camera_id) {
  for (auto& w : workers_) {
    if (w->setup().id == camera_id) return w.get();
  }
  return nullptr;
}

void Service::OnProcessed(const std::string& camera_id, const ProcessedFrame& frame) {
  monocle_dds_CornerPose sample;
  std::string error;
  dds::ToSample(camera_id, frame.sequence, frame.capture_time_ns, frame.camera_clock, frame.corner,
                frame.processing_ns, &sample, &error);
  if (auto s = poses_->Write(sample); !s) std::cerr << "monocled: " << s.error() << "\n";
  if (const auto* w = Find(camera_id)) ros_->PublishPose(w->setup(), frame);
  std::vector<PendingPose> waiting;
  {
    std::lock_guard<std::mutex> lock(pose_mutex_);
    latest_pose_.insert_or_assign(camera_id, frame);
    for (auto it = pending_next_.begin(); it != pending_next_.end();) {
      if (it->camera_id == camera_id) {
        waiting.push_back(std::move(*it));
        it = pending_next_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const auto& w : waiting) ReplyPose(w.client_id, w.request_id, 0, "", camera_id, &frame);
}

void Service::PublishStatus() {
  std::vector<std::pair<const CameraSetup*, WorkerStatus>> statuses;
  for (auto& w : workers_) statuses.emplace_back(&w->setup(), PublishStatusOf(*w, true));
  const int64_t now_ns = UnixNowNs();
  ros_->PublishDiagnostics(statuses, now_ns);
  std::lock_guard<std::mutex> lock(ros_intrinsics_mutex_);
  for (auto& w : workers_) {
    if (const auto it = ros_intrinsics_.find(w->setup().id); it != ros_intrinsics_.end())
      ros_->PublishCameraInfo(w->setup(), it->second, now_ns);
  }
}

WorkerStatus Service::PublishStatusOf(CameraWorker& worker, bool new_period) {
  const WorkerStatus st = worker.Snapshot(new_period);
  const auto& setup = worker.setup();
  monocle_dds_CameraStatus out{};
  out.camera_id = Chars(setup.id);
  out.device = Chars(setup.options.device);
  out.role = const_cast<char*>(ToString(setup.role));
  out.state = static_cast<uint8_t>(st.state);
  out.fps = st.fps;
  out.frames = st.frames;
  out.dropped = st.dropped;
  out.skipped = st.skipped;
  out.latency_ms = st.latency_ms;
  out.last_error = Chars(st.last_error);
  out.last_error_ns = st.last_error_ns;
  out.stamp_ns = UnixNowNs();
  std::lock_guard<std::mutex> lock(status_mutex_);
  if (auto s = status_->Write(out); !s) std::cerr << "monocled: " << s.error() << "\n";
  return st;
}

void Service::PublishCalibration(const std::string& camera_id, const CameraCalibration& cal) {
  {
    std::lock_guard<std::mutex> lock(ros_intrinsics_mutex_);
    ros_intrinsics_[camera_id] = cal.intrinsics;
  }
  const CameraSetup* setup = nullptr;
  for (const auto& c : setup_.cameras) {
    if (c.id == camera_id) setup = &c;
  }
  const std::string text = FormatCalibration(cal);
  monocle_dds_Calibration out{};
  out.camera_id = Chars(camera_id);
  out.revision = revisions_[camera_id];
  out.updated_ns = UnixNowNs();
  const auto& k = cal.intrinsics;
  out.width_px = k.width_px;
  out.height_px = k.height_px;
  out.fx = k.fx;
  out.fy = k.fy;
  out.cx = k.cx;
  out.cy = k.cy;
  for (int i = 0; i < 8; ++i) out.distortion[i] = k.distortion[static_cast<size_t>(i)];
  out.has_floor = cal.floor.has_value();
  if (cal.floor) {
    out.floor_height_m = cal.floor->pose.height_m;
    out.floor_pitch = cal.floor->pose.pitch_rad;
    out.floor_yaw = cal.floor->pose.yaw_rad;
    out.floor_roll = cal.floor->pose.roll_rad;
    const auto sigma = cal.floor->Sigma();
    for (int i = 0; i < 4; ++i) out.floor_sigma[i] = sigma[i];
    out.floor_rms_px = cal.floor->rms_px;
  }
  const std::optional<double> ceiling = setup != nullptr && setup->ceiling_distance_m
                                            ? setup->ceiling_distance_m
                                            : cal.ceiling_distance_m;
  out.has_ceiling = ceiling.has_value();
  out.ceiling_distance_m = ceiling.value_or(0);
  out.file = setup != nullptr ? Chars(setup->calibration_path) : Chars("");
  out.text = Chars(text);
  if (auto s = calibrations_->Write(out); !s) std::cerr << "monocled: " << s.error() << "\n";
}

void Service::ServePointRequests() {
  while (!stop_) {
    auto taken = point_requests_->Take<PointRequest>(kPoll, [](const monocle_dds_PointRequest& r) {
      PointRequest out{Text(r.client_id), Text(r.camera_id), r.request_id, r.pixel_sigma_px, {}};
      out.points.reserve(r.points._length);
      for (uint32_t i = 0; i < r.points._length; ++i) {
        const auto& q = r.points._buffer[i];
        out.points.push_back({q.u, q.v, q.paired, q.floor_u, q.floor_v});
      }
      return out;
    });
    if (!taken) continue;
    for (const auto& r : *taken) {
      RequestAnswer answer;
      {
        std::shared_lock<std::shared_mutex> lock(floor_mutex_);
        answer = AnswerPointRequest(floor_calibrations_, r.camera_id, r.points, r.sigma);
      }
      std::vector<monocle_dds_PointResult> results(answer.points.size());
      std::vector<monocle_dds_PointError> errors;
      for (size_t i = 0; i < answer.points.size(); ++i) {
        const auto& a = answer.points[i];
        auto& out = results[i];
        out.status = static_cast<uint8_t>(a.status);
        const auto sigma = a.measurement.Sigma();
        out.x = a.measurement.p_robot_m.x();
        out.y = a.measurement.p_robot_m.y();
        out.z = a.measurement.p_robot_m.z();
        for (int c = 0; c < 3; ++c) out.sigma[c] = sigma[c];
        if (a.status != PointStatus::kMeasured)
          errors.push_back({static_cast<uint32_t>(i), Chars(a.error)});
      }
      monocle_dds_PointReply reply{};
      reply.client_id = Chars(r.client_id);
      reply.request_id = r.request_id;
      reply.status = static_cast<uint8_t>(answer.status);
      reply.error = Chars(answer.error);
      reply.points._buffer = results.data();
      reply.points._length = reply.points._maximum = static_cast<uint32_t>(results.size());
      reply.points._release = false;
      reply.point_errors._buffer = errors.data();
      reply.point_errors._length = reply.point_errors._maximum =
          static_cast<uint32_t>(errors.size());
      reply.point_errors._release = false;
      if (auto s = point_replies_->Publish(reply); !s)
        std::cerr << "monocled: " << s.error() << "\n";
    }
  }
}

void Service::ReplyPose(const std::string& client_id, uint64_t request_id, uint8_t status,
                        const std::string& error, const std::string& camera_id,
                        const ProcessedFrame* frame) {
  monocle_dds_PoseReply reply{};
  reply.client_id = Chars(client_id);
  reply.request_id = request_id;
  reply.status = status;
  reply.error = Chars(error);
  std::string pose_error;
  if (frame != nullptr) {
    dds::ToSample(camera_id, frame->sequence, frame->capture_time_ns, frame->camera_clock,
                  frame->corner, frame->processing_ns, &reply.pose, &pose_error);
  } else {
    reply.pose.camera_id = Chars(camera_id);
    reply.pose.error = Chars(pose_error);
    reply.pose.suspect_reason = Chars(pose_error);
  }
  if (auto s = pose_replies_->Publish(reply); !s) std::cerr << "monocled: " << s.error() << "\n";
}

void Service::ServePoseRequests() {
  while (!stop_) {
    auto taken = pose_requests_->Take<PoseRequest>(kPoll, [](const monocle_dds_PoseRequest& r) {
      return PoseRequest{Text(r.client_id), Text(r.camera_id), r.request_id, r.which};
    });
    // Next-frame requests that waited too long: the camera gives no frames.
    std::vector<PendingPose> expired;
    {
      std::lock_guard<std::mutex> lock(pose_mutex_);
      const auto now = std::chrono::steady_clock::now();
      for (auto it = pending_next_.begin(); it != pending_next_.end();) {
        if (it->deadline < now) {
          expired.push_back(std::move(*it));
          it = pending_next_.erase(it);
        } else {
          ++it;
        }
      }
    }
    for (const auto& e : expired) {
      ReplyPose(e.client_id, e.request_id, 2,
                "no frame from camera '" + e.camera_id + "' within " +
                    std::to_string(kFrameWait.count() / 1000) + " s (see monocle status)",
                e.camera_id, nullptr);
    }
    if (!taken) continue;
    for (const auto& r : *taken) {
      const CameraWorker* w = Find(r.camera_id);
      if (w == nullptr || !w->setup().corner()) {
        ReplyPose(r.client_id, r.request_id, 1,
                  w == nullptr ? "unknown camera '" + r.camera_id + "'"
                               : "camera '" + r.camera_id + "' is not a corner camera",
                  r.camera_id, nullptr);
        continue;
      }
      if (r.which > 1) {
        ReplyPose(r.client_id, r.request_id, 1,
                  "which must be 0 (latest pose) or 1 (next frame), not " + std::to_string(r.which),
                  r.camera_id, nullptr);
        continue;
      }
      std::unique_lock<std::mutex> lock(pose_mutex_);
      if (r.which == 1) {
        pending_next_.push_back({r.client_id, r.camera_id, r.request_id,
                                 std::chrono::steady_clock::now() + kFrameWait});
        continue;
      }
      const auto it = latest_pose_.find(r.camera_id);
      if (it == latest_pose_.end()) {
        lock.unlock();
        ReplyPose(r.client_id, r.request_id, 2,
                  "no pose yet from camera '" + r.camera_id + "' (see monocle status)", r.camera_id,
                  nullptr);
        continue;
      }
      const ProcessedFrame frame = it->second;
      lock.unlock();
      ReplyPose(r.client_id, r.request_id, 0, "", r.camera_id, &frame);
    }
  }
}

void Service::ServeFloorCalibrationRequests() {
  while (!stop_) {
    auto taken = floor_requests_->Take<FloorRequest>(
        kPoll, [](const monocle_dds_FloorCalibrationRequest& r) {
          return FloorRequest{Text(r.client_id), Text(r.camera_id), r.request_id,
                              r.board_cols,      r.board_rows,      r.square_m};
        });
    if (!taken) continue;
    for (const auto& r : *taken) {
      monocle_dds_FloorCalibrationReply reply{};
      reply.client_id = Chars(r.client_id);
      reply.request_id = r.request_id;
      std::string error, file;
      auto fail = [&](uint8_t status, const std::string& why) {
        reply.status = status;
        error = why;
      };
      CameraWorker* w = Find(r.camera_id);
      const auto spec =
          ParseBoardSize(std::to_string(r.cols) + "x" + std::to_string(r.rows), r.square_m);
      if (w == nullptr) {
        fail(1, "unknown camera '" + r.camera_id + "'");
      } else if (!w->setup().floor()) {
        fail(1, "camera '" + r.camera_id + "' is not a floor camera (role " +
                    ToString(w->setup().role) + ")");
      } else if (!spec) {
        fail(1, spec.error().message);
      } else if (auto frame = w->NextFrame(kFrameWait); !frame) {
        fail(2, frame.error().message);
      } else {
        CameraCalibration cal = w->calibration();
        const auto result =
            CalibrateFloorFromImage(frame->grey, cal.intrinsics, *spec,
                                    FloorCalibrationMethod::kFull, cal.intrinsics_covariance);
        if (!result) {
          fail(2, "frame " + std::to_string(frame->sequence) + ": " + result.error().message);
        } else {
          cal.floor = result->calibration;
          file = w->setup().calibration_path;
          std::lock_guard<std::mutex> lock(calibration_mutex_);
          if (auto saved = SaveCalibrationFileAtomically(file, cal); !saved) {
            fail(2, saved.error().message);
          } else {
            w->SetCalibration(cal);
            {
              std::unique_lock<std::shared_mutex> floor_lock(floor_mutex_);
              floor_calibrations_[r.camera_id] = cal;
            }
            reply.revision = ++revisions_[r.camera_id];
            PublishCalibration(r.camera_id, cal);
            const auto& f = result->calibration;
            reply.height_m = f.pose.height_m;
            reply.pitch = f.pose.pitch_rad;
            reply.yaw = f.pose.yaw_rad;
            reply.roll = f.pose.roll_rad;
            const auto sigma = f.Sigma();
            for (int i = 0; i < 4; ++i) reply.sigma[i] = sigma[i];
            reply.rms_px = f.rms_px;
            reply.corners = static_cast<uint32_t>(result->corners);
            reply.frame_sequence = frame->sequence;
          }
        }
      }
      reply.error = Chars(error);
      reply.file = Chars(file);
      if (auto s = floor_replies_->Publish(reply); !s)
        std::cerr << "monocled: " << s.error() << "\n";
    }
  }
}

}  // namespace monocle
