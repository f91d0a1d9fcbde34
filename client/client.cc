#include "monocle/client.h"

#include <unistd.h>

#include <atomic>
#include <map>
#include <mutex>
#include <thread>

#include "idl/monocle.h"
#include "service/server/dds.h"

namespace monocle {
namespace {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

// Same history and durability as the service's endpoints (service/server/reply_publisher.h).
constexpr dds::EndpointQos kRequestQos{64, false};
constexpr dds::EndpointQos kReplyQos{1, true};
constexpr milliseconds kPoll{100};

std::string Text(const char* s) { return s != nullptr ? s : ""; }

ClientError DdsFailure(const Error& e) { return {ClientError::Code::kDds, e.message}; }

ClientError NoService(int domain, milliseconds timeout, const std::string& what) {
  return {ClientError::Code::kNoService, "no " + what + " from the monocle service on DDS domain " +
                                             std::to_string(domain) + " within " +
                                             std::to_string(timeout.count()) +
                                             " ms: is monocled running, on that domain?"};
}

Pose ToPose(const monocle_dds_CornerPose& s) {
  Pose p;
  p.camera_id = Text(s.camera_id);
  p.frame_sequence = s.frame_sequence;
  p.capture_time_ns = s.capture_time_ns;
  p.camera_clock = s.time_source == 1;
  p.valid = s.status == 0;
  p.error = Text(s.error);
  p.x_m = s.x;
  p.y_m = s.y;
  p.z_m = s.z;
  p.pan_rad = s.pan;
  p.tilt_rad = s.tilt;
  p.swing_rad = s.swing;
  for (size_t i = 0; i < 4; ++i) p.quaternion_wxyz[i] = s.quaternion[i];
  for (size_t i = 0; i < 25; ++i) p.covariance[i] = s.covariance[i];
  p.corner_px = {s.corner_px[0], s.corner_px[1]};
  p.rms_px = s.rms_px;
  p.processing_ns = s.processing_ns;
  p.tracked = s.tracked;
  p.suspect = s.suspect;
  p.suspect_reason = Text(s.suspect_reason);
  return p;
}

CameraStatus ToStatus(const monocle_dds_CameraStatus& s) {
  CameraStatus c;
  c.camera_id = Text(s.camera_id);
  c.device = Text(s.device);
  c.role = Text(s.role);
  c.state = static_cast<CameraState>(s.state);
  c.fps = s.fps;
  c.frames = s.frames;
  c.dropped = s.dropped;
  c.skipped = s.skipped;
  c.latency_ms = s.latency_ms;
  c.last_error = Text(s.last_error);
  c.last_error_ns = s.last_error_ns;
  c.stamp_ns = s.stamp_ns;
  return c;
}

Calibration ToCalibration(const monocle_dds_Calibration& s) {
  Calibration c;
  c.camera_id = Text(s.camera_id);
  c.revision = s.revision;
  c.updated_ns = s.updated_ns;
  c.width_px = s.width_px;
  c.height_px = s.height_px;
  c.fx = s.fx;
  c.fy = s.fy;
  c.cx = s.cx;
  c.cy = s.cy;
  for (size_t i = 0; i < 8; ++i) c.distortion[i] = s.distortion[i];
  if (s.has_floor) {
    c.floor =
        FloorPoseEstimate{s.floor_height_m,
                          s.floor_pitch,
                          s.floor_yaw,
                          s.floor_roll,
                          {s.floor_sigma[0], s.floor_sigma[1], s.floor_sigma[2], s.floor_sigma[3]},
                          s.floor_rms_px};
  }
  if (s.has_ceiling) c.ceiling_distance_m = s.ceiling_distance_m;
  c.file = Text(s.file);
  c.text = Text(s.text);
  return c;
}

ClientError::Code FromReplyStatus(uint8_t status) {
  return status == 1 ? ClientError::Code::kInvalidRequest : ClientError::Code::kFailed;
}

// The request and reply endpoints of one kind of request, opened on first use.
template <typename Request, typename Reply>
struct Channel {
  std::mutex mutex;  // one call of this kind at a time: replies are taken by one caller
  std::unique_ptr<dds::Endpoint<Request>> requests;
  std::unique_ptr<dds::Endpoint<Reply>> replies;
};

}  // namespace

std::ostream& operator<<(std::ostream& os, const ClientError& e) { return os << e.message; }

const char* ToString(CameraState state) {
  switch (state) {
    case CameraState::kStreaming:
      return "streaming";
    case CameraState::kReconnecting:
      return "reconnecting";
    case CameraState::kStopped:
      return "stopped";
  }
  return "unknown";
}

struct Subscription::State {
  std::atomic<bool> stop{false};
  std::thread thread;
  ~State() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
};

Subscription::Subscription() = default;
Subscription::~Subscription() = default;
Subscription::Subscription(Subscription&&) noexcept = default;
Subscription& Subscription::operator=(Subscription&&) noexcept = default;
void Subscription::stop() { state_.reset(); }

struct Client::Impl {
  Options options;
  std::shared_ptr<dds::Entity> participant;
  std::string client_id;
  std::atomic<uint64_t> next_request{1};
  Channel<monocle_dds_PointRequest, monocle_dds_PointReply> points;
  Channel<monocle_dds_PoseRequest, monocle_dds_PoseReply> poses;
  Channel<monocle_dds_FloorCalibrationRequest, monocle_dds_FloorCalibrationReply> floor;

  template <typename Req, typename Rep>
  std::optional<ClientError> Ensure(Channel<Req, Rep>& ch, const dds_topic_descriptor_t* req_type,
                                    const char* req_topic, const dds_topic_descriptor_t* rep_type,
                                    const char* rep_topic) {
    if (ch.requests) return std::nullopt;
    // The reply reader first, so it exists before any request can be answered.
    auto replies =
        dds::Endpoint<Rep>::Open(participant, rep_type, rep_topic, false, true, kReplyQos);
    if (!replies) return DdsFailure(replies.error());
    auto requests =
        dds::Endpoint<Req>::Open(participant, req_type, req_topic, true, false, kRequestQos);
    if (!requests) return DdsFailure(requests.error());
    ch.replies = std::make_unique<dds::Endpoint<Rep>>(std::move(replies).value());
    ch.requests = std::make_unique<dds::Endpoint<Req>>(std::move(requests).value());
    return std::nullopt;
  }

  // Sends `request` (its client id and request id are set here) and waits for its reply;
  // `convert` turns the reply into the result.
  template <typename Out, typename Req, typename Rep, typename Convert>
  ClientResult<Out> Call(Channel<Req, Rep>& ch, Req& request, const char* what, Convert convert) {
    const auto deadline = Clock::now() + options.timeout;
    if (!ch.requests->WaitForReader(options.timeout))
      return NoService(options.domain, options.timeout, what);
    const uint64_t id = next_request++;
    request.client_id = client_id.data();
    request.request_id = id;
    if (auto w = ch.requests->Write(request); !w) return DdsFailure(w.error());
    while (Clock::now() < deadline) {
      const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now());
      auto taken = ch.replies->template Take<std::optional<ClientResult<Out>>>(
          std::max(milliseconds(1), std::min(left, kPoll)),
          [&](const Rep& r) -> std::optional<ClientResult<Out>> {
            if (r.request_id != id || r.client_id == nullptr || client_id != r.client_id)
              return std::nullopt;  // another client's, or an old one of ours
            return convert(r);
          });
      if (!taken) return DdsFailure(taken.error());
      for (auto& reply : *taken) {
        if (reply) return std::move(*reply);
      }
    }
    return NoService(options.domain, options.timeout, what);
  }

  template <typename Sample, typename Out, typename Convert>
  ClientResult<Subscription> Subscribe(const dds_topic_descriptor_t* type, const char* topic,
                                       dds::EndpointQos qos, Convert convert,
                                       std::function<void(const Out&)> callback) {
    auto reader = dds::Endpoint<Sample>::Open(participant, type, topic, false, true, qos);
    if (!reader) return DdsFailure(reader.error());
    Subscription sub;
    sub.state_ = std::make_unique<Subscription::State>();
    auto* state = sub.state_.get();
    state->thread =
        std::thread([state, reader = std::move(reader).value(), convert, callback]() mutable {
          while (!state->stop) {
            auto taken = reader.template Take<std::optional<Out>>(kPoll, convert);
            if (!taken) continue;
            for (const auto& out : *taken) {
              if (out && !state->stop) callback(*out);
            }
          }
        });
    return sub;
  }

  // Every instance's latest sample of a transient-local topic (one per camera).
  template <typename Sample, typename Out, typename Convert>
  ClientResult<std::vector<Out>> Current(const dds_topic_descriptor_t* type, const char* topic,
                                         const char* what, Convert convert) {
    auto reader = dds::Endpoint<Sample>::Open(participant, type, topic, false, true, {1, true});
    if (!reader) return DdsFailure(reader.error());
    std::map<std::string, Out> by_camera;
    const auto deadline = Clock::now() + options.timeout;
    // Kept samples arrive together once the service is discovered: wait for the first, then
    // collect for a short while (samples keep coming, so a quiet spell may never happen).
    std::optional<Clock::time_point> first;
    while (Clock::now() < deadline && (!first || Clock::now() - *first < 3 * kPoll)) {
      auto taken = reader->template Take<Out>(kPoll, convert);
      if (!taken) return DdsFailure(taken.error());
      if (!taken->empty() && !first) first = Clock::now();
      for (auto& out : *taken) by_camera.insert_or_assign(out.camera_id, std::move(out));
    }
    if (by_camera.empty()) return NoService(options.domain, options.timeout, what);
    std::vector<Out> out;
    for (auto& [id, value] : by_camera) out.push_back(std::move(value));
    return out;
  }
};

Client::Client(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Client::~Client() = default;
Client::Client(Client&&) noexcept = default;
Client& Client::operator=(Client&&) noexcept = default;

ClientResult<Client> Client::open(Options options) {
  if (options.domain < 0 || options.domain > 232)
    return ClientError{ClientError::Code::kInvalidRequest, "the DDS domain must be 0..232"};
  auto participant = dds::CreateParticipant(options.domain);
  if (!participant) return DdsFailure(participant.error());
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->participant = *participant;
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  // Unique among the service's clients: host, process and this client's address.
  impl->client_id = std::string(host) + "/" + std::to_string(::getpid()) + "/" +
                    std::to_string(reinterpret_cast<uintptr_t>(impl.get()));
  return Client(std::move(impl));
}

ClientResult<std::vector<MeasuredPoint>> Client::measure(const std::string& camera,
                                                         const std::vector<PixelQuery>& pixels,
                                                         double pixel_sigma_px) {
  auto& ch = impl_->points;
  std::lock_guard<std::mutex> lock(ch.mutex);
  if (auto e = impl_->Ensure(ch, &monocle_dds_PointRequest_desc, dds::kPointRequestTopic,
                             &monocle_dds_PointReply_desc, dds::kPointReplyTopic))
    return *e;
  std::vector<monocle_dds_PixelQuery> queries;
  queries.reserve(pixels.size());
  for (const auto& p : pixels) {
    queries.push_back({p.u, p.v, p.floor_px.has_value(), p.floor_px ? (*p.floor_px)[0] : 0,
                       p.floor_px ? (*p.floor_px)[1] : 0});
  }
  monocle_dds_PointRequest request{};
  request.camera_id = const_cast<char*>(camera.c_str());
  request.pixel_sigma_px = pixel_sigma_px;
  request.points._buffer = queries.data();
  request.points._length = request.points._maximum = static_cast<uint32_t>(queries.size());
  request.points._release = false;
  return impl_->Call<std::vector<MeasuredPoint>>(
      ch, request, "point reply",
      [](const monocle_dds_PointReply& r) -> ClientResult<std::vector<MeasuredPoint>> {
        if (r.status != 0) return ClientError{FromReplyStatus(r.status), Text(r.error)};
        std::vector<MeasuredPoint> out(r.points._length);
        for (uint32_t i = 0; i < r.points._length; ++i) {
          const auto& q = r.points._buffer[i];
          out[i].status = static_cast<MeasuredPoint::Status>(q.status);
          out[i].p_robot_m = {q.x, q.y, q.z};
          out[i].sigma_m = {q.sigma[0], q.sigma[1], q.sigma[2]};
        }
        for (uint32_t i = 0; i < r.point_errors._length; ++i) {
          const auto& e = r.point_errors._buffer[i];
          if (e.index < out.size()) out[e.index].error = Text(e.message);
        }
        return out;
      });
}

ClientResult<Pose> Client::pose(const std::string& camera, PoseWhich which) {
  auto& ch = impl_->poses;
  std::lock_guard<std::mutex> lock(ch.mutex);
  if (auto e = impl_->Ensure(ch, &monocle_dds_PoseRequest_desc, dds::kPoseRequestTopic,
                             &monocle_dds_PoseReply_desc, dds::kPoseReplyTopic))
    return *e;
  monocle_dds_PoseRequest request{};
  request.camera_id = const_cast<char*>(camera.c_str());
  request.which = which == PoseWhich::kLatest ? 0 : 1;
  return impl_->Call<Pose>(ch, request, "pose reply",
                           [](const monocle_dds_PoseReply& r) -> ClientResult<Pose> {
                             if (r.status != 0)
                               return ClientError{FromReplyStatus(r.status), Text(r.error)};
                             return ToPose(r.pose);
                           });
}

ClientResult<FloorCalibrationResult> Client::calibrate_floor(const std::string& camera,
                                                             int board_cols, int board_rows,
                                                             double square_m) {
  auto& ch = impl_->floor;
  std::lock_guard<std::mutex> lock(ch.mutex);
  if (auto e = impl_->Ensure(
          ch, &monocle_dds_FloorCalibrationRequest_desc, dds::kFloorCalibrationRequestTopic,
          &monocle_dds_FloorCalibrationReply_desc, dds::kFloorCalibrationReplyTopic))
    return *e;
  monocle_dds_FloorCalibrationRequest request{};
  request.camera_id = const_cast<char*>(camera.c_str());
  request.board_cols = board_cols;
  request.board_rows = board_rows;
  request.square_m = square_m;
  return impl_->Call<FloorCalibrationResult>(
      ch, request, "floor calibration reply",
      [](const monocle_dds_FloorCalibrationReply& r) -> ClientResult<FloorCalibrationResult> {
        if (r.status != 0) return ClientError{FromReplyStatus(r.status), Text(r.error)};
        FloorCalibrationResult out;
        out.floor = {
            r.height_m, r.pitch, r.yaw, r.roll, {r.sigma[0], r.sigma[1], r.sigma[2], r.sigma[3]},
            r.rms_px};
        out.corners = r.corners;
        out.frame_sequence = r.frame_sequence;
        out.file = Text(r.file);
        out.revision = r.revision;
        return out;
      });
}

ClientResult<std::vector<CameraStatus>> Client::status() {
  return impl_->Current<monocle_dds_CameraStatus, CameraStatus>(
      &monocle_dds_CameraStatus_desc, dds::kStatusTopic, "status", ToStatus);
}

ClientResult<std::vector<Calibration>> Client::calibrations() {
  return impl_->Current<monocle_dds_Calibration, Calibration>(
      &monocle_dds_Calibration_desc, dds::kCalibrationTopic, "calibration", ToCalibration);
}

ClientResult<Subscription> Client::subscribe_poses(std::function<void(const Pose&)> on_pose,
                                                   const std::string& camera) {
  // A deeper reader history than the writer's: a briefly slow callback loses nothing.
  return impl_->Subscribe<monocle_dds_CornerPose, Pose>(
      &monocle_dds_CornerPose_desc, dds::kPoseTopic, {16, false},
      [camera](const monocle_dds_CornerPose& s) -> std::optional<Pose> {
        if (!camera.empty() && camera != Text(s.camera_id)) return std::nullopt;
        return ToPose(s);
      },
      std::move(on_pose));
}

ClientResult<Subscription> Client::subscribe_status(
    std::function<void(const CameraStatus&)> on_status) {
  return impl_->Subscribe<monocle_dds_CameraStatus, CameraStatus>(
      &monocle_dds_CameraStatus_desc, dds::kStatusTopic, {1, true},
      [](const monocle_dds_CameraStatus& s) -> std::optional<CameraStatus> { return ToStatus(s); },
      std::move(on_status));
}

}  // namespace monocle
