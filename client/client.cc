#include "monocle/client.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>

#include "idl/protocol/convert.h"
#include "idl/protocol/service_endpoints.h"
#include "idl/protocol/wire.h"

namespace monocle {
namespace {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

constexpr milliseconds kPoll{100};
// Kept statuses of every camera arrive together once a service is discovered; services found
// later follow within this.
constexpr milliseconds kDiscoveryGrace{1000};
// A camera whose status has not been heard for this long is taken as gone (its service
// stopped or crashed): statuses come every status period, 1 s by default.
constexpr milliseconds kStatusStale{10000};
// How long a camera once found is taken to stay where it was.
constexpr milliseconds kResolvedFresh{1000};
// Why data on a camera's topic from a participant other than its service's is not taken.
constexpr const char* kNotTheServingParticipant =
    "from a participant that does not serve it (spoofed, or another service misconfigured; on "
    "a network you do not control, use DDS Security)";

ClientError DdsFailure(const Error& e) {
  if (e.code == ErrorCode::kPermissionDenied) return {ClientError::Code::kNotPermitted, e.message};
  return {ClientError::Code::kDds, e.message};
}

ClientError NoService(int domain, milliseconds timeout, const std::string& what) {
  return {ClientError::Code::kNoService, "no " + what + " from the monocle service on DDS domain " +
                                             std::to_string(domain) + " within " +
                                             std::to_string(timeout.count()) +
                                             " ms: is monocled running, on that domain?"};
}

ClientError::Code CodeOf(uint32_t status) {
  return status == monocle_msgs_msg_dds__REQUEST_INVALID ? ClientError::Code::kInvalidRequest
                                                         : ClientError::Code::kFailed;
}

bool HasRole(const CameraStatus& s, const std::string& role) {
  return role.empty() || s.role.find(role) != std::string::npos;
}

using PointService = dds::ServiceClient<monocle_msgs_srv_dds__MeasurePoints_Request_,
                                        monocle_msgs_srv_dds__MeasurePoints_Response_>;
using PoseService = dds::ServiceClient<monocle_msgs_srv_dds__GetPose_Request_,
                                       monocle_msgs_srv_dds__GetPose_Response_>;
using FloorService = dds::ServiceClient<monocle_msgs_srv_dds__CalibrateFloor_Request_,
                                        monocle_msgs_srv_dds__CalibrateFloor_Response_>;

// The service clients of one kind, one per camera namespace, opened on first use.
template <typename Service>
struct Channel {
  std::mutex mutex;  // one call of this kind at a time
  std::map<std::string, std::unique_ptr<Service>> by_namespace;
};

// Every camera status heard, by (namespace, service).
class Directory {
 public:
  struct Entry {
    CameraStatus status;
    Clock::time_point heard;
    std::string source;  // the participant its status came from (dds::WriterSources)
    dds_instance_handle_t writer = 0;
  };

  static Result<std::unique_ptr<Directory>> Open(const std::shared_ptr<dds::Entity>& p) {
    auto reader = dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>::Open(
        p, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic, false, true,
        wire::kDirectoryReaderQos);
    if (!reader) return reader.error();
    auto d = std::make_unique<Directory>();
    d->reader_ = std::make_unique<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>>(
        std::move(reader).value());
    d->sources_ = std::make_unique<dds::WriterSources>(d->reader_->reader());
    return d;
  }

  // Takes what has arrived, waiting up to `wait` for something; returns the live entries.
  std::vector<Entry> Update(milliseconds wait) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto taken = reader_->Take<Entry>(
        wait, [&](const monocle_msgs_msg_dds__CameraStatus_& s, const dds_sample_info_t& info) {
          return Entry{wire::FromSample(s), Clock::time_point{},
                       sources_->Of(info.publication_handle), info.publication_handle};
        });
    const auto now = Clock::now();
    if (taken) {
      for (auto& e : *taken) {
        if (!first_heard_) first_heard_ = now;
        e.heard = now;
        auto key = std::make_tuple(e.status.ros_namespace, e.status.service, e.source);
        entries_.insert_or_assign(std::move(key), std::move(e));
      }
    }
    std::vector<Entry> live;
    for (auto it = entries_.begin(); it != entries_.end();) {
      // A writer that has left (its participant closed) says no more: forgotten at once.
      if (it->second.writer != 0 && !StillMatched(it->second.writer)) {
        it = entries_.erase(it);
        continue;
      }
      if (now - it->second.heard < kStatusStale) live.push_back(it->second);
      ++it;
    }
    return live;
  }

  std::optional<Clock::time_point> first_heard() {
    std::lock_guard<std::mutex> lock(mutex_);
    return first_heard_;
  }

  // Whether every status writer discovered so far (one per camera of each service) has been
  // heard: a slow process (a loaded machine, a sanitizer) discovers a second service later
  // than the first, and a list cut short would hide it.
  bool HeardEveryWriter() {
    std::lock_guard<std::mutex> lock(mutex_);
    dds_subscription_matched_status_t st{};
    if (dds_get_subscription_matched_status(reader_->reader(), &st) < 0) return true;
    return entries_.size() >= st.current_count;
  }

  // The one participant serving namespace `ns` by the statuses heard (empty: none heard yet,
  // or several claim it).
  std::string ServingSource(const std::string& ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = Clock::now();
    std::set<std::string> sources;
    for (const auto& [key, e] : entries_) {
      if (e.status.ros_namespace == ns && now - e.heard < kStatusStale &&
          (e.status.state == CameraState::kStreaming ||
           e.status.state == CameraState::kReconnecting))
        sources.insert(e.source);
    }
    return sources.size() == 1 ? *sources.begin() : "";
  }

 private:
  bool StillMatched(dds_instance_handle_t writer) const {
    dds_builtintopic_endpoint_t* w = dds_get_matched_publication_data(reader_->reader(), writer);
    if (w == nullptr) return false;
    dds_builtintopic_free_endpoint(w);
    return true;
  }

  std::mutex mutex_;
  std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>> reader_;
  std::unique_ptr<dds::WriterSources> sources_;
  // By (namespace, service, source): a participant claiming another's service id is its own.
  std::map<std::tuple<std::string, std::string, std::string>, Entry> entries_;
  std::optional<Clock::time_point> first_heard_;
};

// Two services claiming one namespace, in words; empty if none. Two participants are two
// services whatever service id they give (a spoofer may copy the real one's).
std::string Clashes(const std::vector<Directory::Entry>& entries) {
  std::map<std::string, std::map<std::string, std::string>> serving;  // ns -> source -> service
  for (const auto& e : entries) {
    // Stopped or failed (a newcomer that refused the namespace) serves nothing.
    if (e.status.state == CameraState::kStreaming || e.status.state == CameraState::kReconnecting)
      serving[e.status.ros_namespace][e.source.empty() ? e.status.service : e.source] =
          e.status.service;
  }
  std::string out;
  for (const auto& [ns, by_source] : serving) {
    if (by_source.size() < 2) continue;
    // A claimant that copies the service id is told apart by its participant.
    std::set<std::string> ids;
    for (const auto& [source, service] : by_source) ids.insert(service);
    const bool same_ids = ids.size() < by_source.size();
    out += (out.empty() ? "" : "; ") + ns + " is served by " + std::to_string(by_source.size()) +
           " monocled (";
    bool first = true;
    for (const auto& [source, service] : by_source) {
      out += (first ? "" : ", ") + service;
      if (same_ids && source != service) out += " from participant " + source;
      first = false;
    }
    out += ")";
  }
  return out;
}

// A name the caller gave, as errors show it: whole if short, else its start and its length
// (a megabyte of name echoed back helps nobody).
std::string Shown(const std::string& name) {
  constexpr size_t kShown = 64;
  if (name.size() <= kShown) return name;
  return name.substr(0, kShown) + "... (" + std::to_string(name.size()) + " characters)";
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const ClientError& e) { return os << e.message; }

const char* ToString(MapStatus status) {
  switch (status) {
    case MapStatus::kNone:
      return "";
    case MapStatus::kLocated:
      return "located";
    case MapStatus::kAmbiguous:
      return "ambiguous";
    case MapStatus::kContradictsPrior:
      return "contradicts prior";
    case MapStatus::kNoCornerFits:
      return "no corner fits";
  }
  return "";
}

const char* ToString(CameraState state) {
  switch (state) {
    case CameraState::kStreaming:
      return "streaming";
    case CameraState::kReconnecting:
      return "reconnecting";
    case CameraState::kStopped:
      return "stopped";
    case CameraState::kFailed:
      return "failed";
  }
  return "unknown";
}

std::string DuplicateCameras(const std::vector<CameraStatus>& cameras) {
  std::vector<Directory::Entry> entries;
  for (const auto& c : cameras) entries.push_back({c, Clock::now(), c.participant, 0});
  return Clashes(entries);
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
  std::unique_ptr<Directory> directory;
  Channel<PointService> points;
  Channel<PoseService> poses;
  Channel<FloorService> floor;
  std::mutex resolved_mutex;
  std::map<std::string, std::pair<CameraStatus, Clock::time_point>> resolved;

  // The one camera `camera` (an id or a namespace) names, with `role` ("floor", "corner" or
  // any if empty). Waits for the directory until the deadline.
  ClientResult<CameraStatus> Resolve(const std::string& camera, const std::string& role,
                                     Clock::time_point deadline) {
    {
      // A camera named a moment ago is still where it was: no directory scan per request.
      std::lock_guard<std::mutex> lock(resolved_mutex);
      const auto it = resolved.find(camera + "\n" + role);
      if (it != resolved.end() && Clock::now() - it->second.second < kResolvedFresh)
        return it->second.first;
    }
    auto found = ResolveNow(camera, role, deadline);
    if (found) {
      std::lock_guard<std::mutex> lock(resolved_mutex);
      resolved.insert_or_assign(camera + "\n" + role, std::make_pair(*found, Clock::now()));
    }
    return found;
  }

  ClientResult<CameraStatus> ResolveNow(const std::string& camera, const std::string& role,
                                        Clock::time_point deadline) {
    const std::string kind = role.empty() ? "camera" : role + " camera";
    for (bool at_once = true;; at_once = false) {
      // What is known already first: a camera in the directory costs no wait.
      const auto entries = directory->Update(at_once ? milliseconds(0) : kPoll);
      std::vector<CameraStatus> named;
      std::vector<Directory::Entry> named_entries;
      for (const auto& e : entries) {
        if (e.status.camera_id == camera || e.status.ros_namespace == camera) {
          named.push_back(e.status);
          named_entries.push_back(e);
        }
      }
      std::set<std::string> namespaces;
      for (const auto& s : named) namespaces.insert(s.ros_namespace);
      if (namespaces.size() > 1) {
        std::string list;
        for (const auto& ns : namespaces) list += (list.empty() ? "" : ", ") + ns;
        return ClientError{ClientError::Code::kInvalidRequest,
                           "camera '" + Shown(camera) + "' is on several robots (" + list +
                               "): name it by its namespace"};
      }
      if (named.size() > 1) {
        if (const std::string clash = Clashes(named_entries); !clash.empty()) {
          return ClientError{ClientError::Code::kInvalidRequest,
                             "camera '" + Shown(camera) + "': " + clash +
                                 "; give each robot its own ros_namespace"};
        }
      }
      if (!named.empty()) {
        // The newest status of the one service that serves it (streaming or reconnecting),
        // else of one that failed, else of one that stopped.
        const auto rank = [](CameraState s) {
          return s == CameraState::kStopped ? 0 : s == CameraState::kFailed ? 1 : 2;
        };
        std::sort(named.begin(), named.end(), [&](const auto& a, const auto& b) {
          return std::make_tuple(rank(a.state), a.stamp_ns) >
                 std::make_tuple(rank(b.state), b.stamp_ns);
        });
        const CameraStatus& s = named.front();
        if (!HasRole(s, role)) {
          return ClientError{
              ClientError::Code::kInvalidRequest,
              "camera '" + s.camera_id + "' is not a " + kind + " (role " + s.role + ")"};
        }
        return s;
      }
      const auto first = directory->first_heard();
      const auto now = Clock::now();
      if (first && (now - *first > kDiscoveryGrace || now >= deadline)) {
        std::string known;
        for (const auto& e : entries) {
          if (HasRole(e.status, role))
            known += (known.empty() ? "" : ", ") + e.status.camera_id + " (" +
                     e.status.ros_namespace + ")";
        }
        return ClientError{ClientError::Code::kInvalidRequest,
                           "unknown camera '" + Shown(camera) + "' on DDS domain " +
                               std::to_string(options.domain) + "; " + kind +
                               "s there: " + (known.empty() ? "none" : known)};
      }
      if (now >= deadline) return NoService(options.domain, options.timeout, "camera status");
    }
  }

  // Sends one request to the service of `camera` and waits for its reply.
  template <typename Out, typename Service, typename Request, typename Convert>
  ClientResult<Out> Call(Channel<Service>& ch, const std::string& camera, const std::string& role,
                         const char* service_name, const dds_topic_descriptor_t* request_type,
                         const dds_topic_descriptor_t* reply_type, Request& request,
                         Convert convert, milliseconds resend_after) {
    const auto deadline = Clock::now() + options.timeout;
    auto status = Resolve(camera, role, deadline);
    if (!status) return status.error();
    const std::string& ns = status->ros_namespace;
    std::lock_guard<std::mutex> lock(ch.mutex);
    auto& service = ch.by_namespace[ns];
    if (!service) {
      auto opened = Service::Open(participant, request_type, reply_type, ns, service_name);
      if (!opened) {
        if (opened.error().code == ErrorCode::kPermissionDenied) {
          return ClientError{ClientError::Code::kNotPermitted,
                             std::string(service_name) + " of camera '" + Shown(camera) +
                                 "': this client's DDS Security permissions (" +
                                 options.security_dir + ") do not allow it" +
                                 (std::string(service_name) == wire::kCalibrateFloor
                                      ? "; floor calibration takes the operator role (monocle "
                                        "security init KEYSTORE --client NAME:operator)"
                                      : "")};
        }
        return DdsFailure(opened.error());
      }
      service = std::make_unique<Service>(std::move(opened).value());
    }
    const std::string what = std::string(service_name) + " reply of camera '" + Shown(camera) + "'";
    auto left = [&] {
      return std::max(milliseconds(1),
                      std::chrono::duration_cast<milliseconds>(deadline - Clock::now()));
    };
    if (!service->WaitForService(left())) return NoService(options.domain, options.timeout, what);
    // Replies from any other participant (a spoofer answering first) are not the camera's.
    service->TrustOnly(directory->ServingSource(ns));
    const uint64_t foreign_before = service->foreign_replies();
    auto reply = service->template Call<ClientResult<Out>>(request, left(), convert, resend_after);
    if (const uint64_t foreign = service->foreign_replies() - foreign_before;
        foreign > 0 && options.on_ignored) {
      options.on_ignored("camera '" + Shown(camera) + "' (" + ns + "): " + std::to_string(foreign) +
                         " " + service_name + " replies not taken: they came " +
                         kNotTheServingParticipant);
    }
    if (!reply) return DdsFailure(reply.error());
    if (!*reply) return NoService(options.domain, options.timeout, what);
    return std::move(**reply);
  }
};

Client::Client(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Client::~Client() = default;
Client::Client(Client&&) noexcept = default;
Client& Client::operator=(Client&&) noexcept = default;

ClientResult<Client> Client::open(Options options) {
  if (options.domain < 0 || options.domain > 232)
    return ClientError{ClientError::Code::kInvalidRequest, "the DDS domain must be 0..232"};
  auto participant = dds::CreateParticipant(options.domain, options.security_dir);
  if (!participant) return DdsFailure(participant.error());
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->participant = *participant;
  // Listening from the start: by the first request the cameras are likely known.
  auto directory = Directory::Open(impl->participant);
  if (!directory) return DdsFailure(directory.error());
  impl->directory = std::move(directory).value();
  return Client(std::move(impl));
}

ClientResult<std::vector<MeasuredPoint>> Client::measure(const std::string& camera,
                                                         const std::vector<PixelQuery>& pixels,
                                                         double pixel_sigma_px) {
  if (pixels.size() > wire::kMaxPointsPerRequest) {
    return ClientError{ClientError::Code::kInvalidRequest,
                       "too many points in one request (" + std::to_string(pixels.size()) + " > " +
                           std::to_string(wire::kMaxPointsPerRequest) + "): split it"};
  }
  wire::PointRequestColumns columns;
  monocle_msgs_srv_dds__MeasurePoints_Request_ request;
  wire::ToSample(pixels, pixel_sigma_px, &columns, &request);
  return impl_->Call<std::vector<MeasuredPoint>>(
      impl_->points, camera, "floor", wire::kMeasurePoints,
      &monocle_msgs_srv_dds__MeasurePoints_Request__desc,
      &monocle_msgs_srv_dds__MeasurePoints_Response__desc, request,
      [](const monocle_msgs_srv_dds__MeasurePoints_Response_& r)
          -> ClientResult<std::vector<MeasuredPoint>> {
        if (wire::EnumValue(r.status) != monocle_msgs_msg_dds__REQUEST_OK)
          return ClientError{CodeOf(wire::EnumValue(r.status)), r.error != nullptr ? r.error : ""};
        auto points = wire::FromSample(r);
        if (!points) return ClientError{ClientError::Code::kFailed, points.error().message};
        return std::move(points).value();
      },
      // Sent again without a reply: a few points are answered in well under a millisecond
      // (bench/service_bench), so after 50 ms one of the two messages was lost; a large batch
      // takes tens of milliseconds to measure and carry, so it waits a second first.
      pixels.size() <= 1000 ? milliseconds(50) : milliseconds(1000));
}

ClientResult<Pose> Client::pose(const std::string& camera, PoseWhich which) {
  monocle_msgs_srv_dds__GetPose_Request_ request{};
  request.which = which == PoseWhich::kLatest ? monocle_msgs_msg_dds__POSE_LATEST
                                              : monocle_msgs_msg_dds__POSE_NEXT_FRAME;
  return impl_->Call<Pose>(
      impl_->poses, camera, "corner", wire::kGetPose, &monocle_msgs_srv_dds__GetPose_Request__desc,
      &monocle_msgs_srv_dds__GetPose_Response__desc, request,
      [](const monocle_msgs_srv_dds__GetPose_Response_& r) -> ClientResult<Pose> {
        if (wire::EnumValue(r.status) != monocle_msgs_msg_dds__REQUEST_OK)
          return ClientError{CodeOf(wire::EnumValue(r.status)), r.error != nullptr ? r.error : ""};
        return wire::FromSample(r.pose);
      },
      milliseconds(250));  // the next frame's pose can take a frame period and its processing
}

ClientResult<FloorCalibrationResult> Client::calibrate_floor(const std::string& camera,
                                                             int board_cols, int board_rows,
                                                             double square_m) {
  return calibrate_floor(camera, board_cols, board_rows, square_m, FloorCalibrationOptions{});
}

ClientResult<FloorCalibrationResult> Client::calibrate_floor(
    const std::string& camera, int board_cols, int board_rows, double square_m,
    const FloorCalibrationOptions& options) {
  monocle_msgs_srv_dds__CalibrateFloor_Request_ request{};
  wire::ToSample(board_cols, board_rows, square_m, options, &request);
  return impl_->Call<FloorCalibrationResult>(
      impl_->floor, camera, "floor", wire::kCalibrateFloor,
      &monocle_msgs_srv_dds__CalibrateFloor_Request__desc,
      &monocle_msgs_srv_dds__CalibrateFloor_Response__desc, request,
      [](const monocle_msgs_srv_dds__CalibrateFloor_Response_& r)
          -> ClientResult<FloorCalibrationResult> {
        if (wire::EnumValue(r.status) != monocle_msgs_msg_dds__REQUEST_OK)
          return ClientError{CodeOf(wire::EnumValue(r.status)), r.error != nullptr ? r.error : ""};
        return wire::FromSample(r);
      },
      milliseconds(0));  // never sent twice: it rewrites the calibration file
}

ClientResult<std::vector<CameraStatus>> Client::status() {
  const auto deadline = Clock::now() + impl_->options.timeout;
  // Wait for the first status, then a little longer for other services' cameras.
  std::vector<Directory::Entry> entries;
  for (;;) {
    entries = impl_->directory->Update(kPoll);
    const auto first = impl_->directory->first_heard();
    const auto now = Clock::now();
    // A second service is discovered a little after the first (its participant, then its
    // writers): a whole listing waits the discovery grace, and on for writers not yet heard.
    if (first && now - *first > kDiscoveryGrace &&
        (impl_->directory->HeardEveryWriter() || now - *first > 2 * kDiscoveryGrace))
      break;
    if (now >= deadline) break;
  }
  if (entries.empty() && impl_->directory->first_heard()) {
    return ClientError{
        ClientError::Code::kNoService,
        "the monocle service on DDS domain " + std::to_string(impl_->options.domain) +
            " stopped sending status (none for " + std::to_string(kStatusStale.count() / 1000) +
            " s): has monocled stopped or stalled?"};
  }
  if (entries.empty()) return NoService(impl_->options.domain, impl_->options.timeout, "status");
  std::vector<CameraStatus> out;
  for (auto& e : entries) {
    e.status.participant = e.source;
    out.push_back(std::move(e.status));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return std::tie(a.ros_namespace, a.service) < std::tie(b.ros_namespace, b.service);
  });
  return out;
}

ClientResult<std::vector<Calibration>> Client::calibrations() {
  auto reader = dds::Endpoint<monocle_msgs_msg_dds__Calibration_>::Open(
      impl_->participant, &monocle_msgs_msg_dds__Calibration__desc, wire::kCalibrationsTopic, false,
      true, wire::kDirectoryReaderQos);
  if (!reader) return DdsFailure(reader.error());
  std::map<std::string, Calibration> by_namespace;
  const auto deadline = Clock::now() + impl_->options.timeout;
  std::optional<Clock::time_point> first;
  dds::WriterSources sources(reader->reader());
  std::map<std::string, std::pair<std::string, int>> ignored;  // namespace -> camera, count
  while (Clock::now() < deadline && (!first || Clock::now() - *first < 3 * kPoll)) {
    auto taken = reader->Take<std::pair<Calibration, std::string>>(
        kPoll, [&](const monocle_msgs_msg_dds__Calibration_& s, const dds_sample_info_t& info) {
          return std::make_pair(wire::FromSample(s), sources.Of(info.publication_handle));
        });
    if (!taken) return DdsFailure(taken.error());
    if (!taken->empty() && !first) first = Clock::now();
    impl_->directory->Update(milliseconds(0));
    for (auto& [c, source] : *taken) {
      // Only the service that serves the camera speaks for its calibration.
      const std::string serving = impl_->directory->ServingSource(c.ros_namespace);
      if (!serving.empty() && source != serving) {
        auto& [camera_id, count] = ignored[c.ros_namespace];
        camera_id = c.camera_id;
        ++count;
        continue;
      }
      auto& kept = by_namespace[c.ros_namespace];
      if (c.revision >= kept.revision) kept = std::move(c);
    }
  }
  for (const auto& [ns, why] : ignored) {
    if (impl_->options.on_ignored)
      impl_->options.on_ignored("camera '" + why.first + "' (" + ns +
                                "): " + std::to_string(why.second) +
                                " calibrations not taken: they came " + kNotTheServingParticipant);
  }
  if (by_namespace.empty())
    return NoService(impl_->options.domain, impl_->options.timeout, "calibration");
  std::vector<Calibration> out;
  for (auto& [ns, c] : by_namespace) out.push_back(std::move(c));
  return out;
}

ClientResult<Subscription> Client::subscribe_poses(std::function<void(const Pose&)> on_pose,
                                                   const std::string& camera) {
  return subscribe_poses(std::move(on_pose), camera, nullptr);
}

namespace {

// The corner pose readers of a subscription, one per camera namespace, each with the
// participants its directory entries say serve it, and the poses it did not deliver.
class PoseReaders {
 public:
  using Reader = dds::Endpoint<monocle_msgs_msg_dds__CornerPose_>;
  PoseReaders(std::shared_ptr<dds::Entity> participant, std::string camera)
      : participant_(std::move(participant)),
        camera_(std::move(camera)),
        waitset_(dds::WaitSet::Create(participant_)) {}

  // Opens readers for new matching cameras, and learns who serves each.
  void Follow(const std::vector<Directory::Entry>& entries) {
    for (auto& [ns, r] : by_namespace_) r.serving.clear();
    for (const auto& e : entries) {
      const auto& s = e.status;
      if (!HasRole(s, "corner")) continue;
      if (!camera_.empty() && camera_ != s.camera_id && camera_ != s.ros_namespace) continue;
      auto& r = by_namespace_[s.ros_namespace];
      r.camera_id = s.camera_id;
      if (s.state == CameraState::kStreaming || s.state == CameraState::kReconnecting)
        r.serving[e.source] = s.service;
      if (r.reader) continue;
      // A deeper history than ROS's default: a briefly slow callback loses nothing.
      auto opened =
          Reader::Open(participant_, &monocle_msgs_msg_dds__CornerPose__desc,
                       wire::CornerPoseTopic(s.ros_namespace).c_str(), false, true, {16, false});
      if (!opened) continue;
      r.reader = std::make_unique<Reader>(std::move(opened).value());
      r.sources = std::make_unique<dds::WriterSources>(r.reader->reader());
      if (waitset_) waitset_->Attach(r.reader->reader());
    }
  }

  bool empty() const { return by_namespace_.empty(); }
  void Wait(milliseconds timeout) {
    if (waitset_) waitset_->Wait(timeout);
  }

  // Delivers what the serving participant wrote; counts the rest.
  void Take(const std::function<void(const Pose&)>& on_pose, const std::atomic<bool>& stop) {
    for (auto& [ns, r] : by_namespace_) {
      if (!r.reader) continue;
      auto taken = r.reader->Take<std::pair<Pose, dds_instance_handle_t>>(
          milliseconds(0), [](const auto& s, const dds_sample_info_t& info) {
            return std::make_pair(wire::FromSample(s), info.publication_handle);
          });
      if (!taken) continue;
      for (const auto& [pose, writer] : *taken) {
        const std::string& source = r.sources->Of(writer);
        if (r.serving.size() != 1 || r.serving.begin()->first != source) {
          ++r.ignored;
          continue;
        }
        if (!stop) on_pose(pose);
      }
    }
  }

  // What was not delivered since the last report, camera by camera.
  void Report(const std::function<void(const std::string&)>& on_ignored) {
    for (auto& [ns, r] : by_namespace_) {
      if (r.ignored == 0) continue;
      std::string why;
      if (r.serving.size() > 1) {
        why = "it is claimed by " + std::to_string(r.serving.size()) + " services (";
        bool first = true;
        for (const auto& [source, service] : r.serving) {
          why += (first ? "" : ", ") + service;
          first = false;
        }
        why += ") and none of them can be trusted until only one is left";
      } else if (r.serving.empty()) {
        why = "no service says it serves it now (stopped, or not heard from yet)";
      } else {
        why = std::string("they came ") + kNotTheServingParticipant;
      }
      if (on_ignored)
        on_ignored("camera '" + r.camera_id + "' (" + ns + "): " + std::to_string(r.ignored) +
                   " corner poses not delivered: " + why);
      r.ignored = 0;
    }
  }

 private:
  struct PerCamera {
    std::string camera_id;
    std::unique_ptr<Reader> reader;
    std::unique_ptr<dds::WriterSources> sources;
    std::map<std::string, std::string> serving;  // source -> service id
    uint64_t ignored = 0;
  };
  std::shared_ptr<dds::Entity> participant_;
  std::string camera_;
  Result<dds::WaitSet> waitset_;
  std::map<std::string, PerCamera> by_namespace_;
};

}  // namespace

ClientResult<Subscription> Client::subscribe_poses(
    std::function<void(const Pose&)> on_pose, const std::string& camera,
    std::function<void(const std::string&)> on_ignored) {
  // Poses travel on each corner camera's own topic: follow the directory and open a reader
  // for every matching camera as it appears (before or after the service starts).
  auto directory = Directory::Open(impl_->participant);
  if (!directory) return DdsFailure(directory.error());
  Subscription sub;
  sub.state_ = std::make_unique<Subscription::State>();
  auto* state = sub.state_.get();
  state->thread = std::thread([state, participant = impl_->participant, camera,
                               directory = std::shared_ptr<Directory>(std::move(directory).value()),
                               on_pose = std::move(on_pose), on_ignored = std::move(on_ignored)] {
    PoseReaders readers(participant, camera);
    auto last_lookup = Clock::now() - kPoll * 10;
    auto last_report = Clock::now();
    while (!state->stop) {
      if (Clock::now() - last_lookup > 5 * kPoll) {
        last_lookup = Clock::now();
        readers.Follow(directory->Update(milliseconds(0)));
      }
      readers.Wait(kPoll);
      readers.Take(on_pose, state->stop);
      if (Clock::now() - last_report > std::chrono::seconds(1)) {
        last_report = Clock::now();
        readers.Report(on_ignored);
      }
      if (readers.empty()) std::this_thread::sleep_for(kPoll);
    }
  });
  return sub;
}

ClientResult<Subscription> Client::subscribe_status(
    std::function<void(const CameraStatus&)> on_status) {
  auto reader = dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>::Open(
      impl_->participant, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic, false,
      true, wire::kDirectoryReaderQos);
  if (!reader) return DdsFailure(reader.error());
  Subscription sub;
  sub.state_ = std::make_unique<Subscription::State>();
  auto* state = sub.state_.get();
  state->thread = std::thread([state, reader = std::move(reader).value(),
                               on_status = std::move(on_status)]() mutable {
    while (!state->stop) {
      auto taken = reader.Take<CameraStatus>(
          kPoll, [](const monocle_msgs_msg_dds__CameraStatus_& s) { return wire::FromSample(s); });
      if (!taken) continue;
      for (const auto& s : *taken) {
        if (!state->stop) on_status(s);
      }
    }
  });
  return sub;
}

}  // namespace monocle
