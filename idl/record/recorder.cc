#include "idl/record/recorder.h"

#include <dds/ddsi/ddsi_serdata.h>

#include <chrono>

#include "idl/monocle_msgs.h"
#include "idl/protocol/wire.h"
#include "idl/record/ros2_schemas.h"
#include "idl/ros2_messages.h"

namespace monocle::record {

struct Recorder::Topic {
  std::string dds_name;  // rt/monocle/sim_corner/pose
  std::string ros_name;  // /monocle/sim_corner/pose
  const dds_topic_descriptor_t* type = nullptr;
  std::string schema_name;  // geometry_msgs/msg/PoseWithCovarianceStamped
  std::string definition;   // ros2msg text
  bool transient_local = false;
  int depth = 10;
  int keep_every = 1;  // 1: every sample; N: every Nth

  dds::Entity topic;  // deleted after its reader (members are destroyed in reverse)
  dds::Entity reader;
  uint16_t channel = 0;
  uint64_t taken = 0;
  uint32_t sequence = 0;
  TopicStats stats;
};

namespace {

using TopicPtr = std::unique_ptr<Recorder::Topic>;

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// What a channel's QoS was, in the form the MCAP ros2 profile asks for (rosbag2 reads it to
// replay with the same QoS).
std::string OfferedQos(bool transient_local, int depth) {
  return "- history: keep_last\n  depth: " + std::to_string(depth) +
         "\n  reliability: reliable\n  durability: " +
         (transient_local ? "transient_local" : "volatile") +
         "\n  deadline:\n    sec: 0\n    nsec: 0\n  lifespan:\n    sec: 0\n    nsec: 0\n"
         "  liveliness: automatic\n  liveliness_lease_duration:\n    sec: 0\n    nsec: 0\n"
         "  avoid_ros_namespace_conventions: false\n";
}

TopicPtr Message(std::string ros_name, const dds_topic_descriptor_t* type, std::string schema,
                 bool transient_local = false, int depth = 64) {
  auto t = std::make_unique<Recorder::Topic>();
  t->dds_name = "rt" + ros_name;
  t->ros_name = std::move(ros_name);
  t->type = type;
  t->definition = Ros2MsgDefinition(schema).value_or("");
  t->schema_name = std::move(schema);
  t->transient_local = transient_local;
  t->depth = depth;
  return t;
}

TopicPtr ServiceSample(const std::string& ns, const char* service, const std::string& srv_type,
                       bool request, const dds_topic_descriptor_t* type) {
  auto t = std::make_unique<Recorder::Topic>();
  t->dds_name = request ? wire::RequestTopic(ns, service) : wire::ReplyTopic(ns, service);
  t->ros_name = ns + "/" + service + (request ? "/request" : "/reply");
  t->type = type;
  t->schema_name = srv_type + (request ? "_Request" : "_Response");
  t->definition = Ros2ServiceSampleDefinition(srv_type, request).value_or("");
  t->depth = 64;
  return t;
}

std::vector<TopicPtr> TopicsToRecord(const RecordOptions& o) {
  std::vector<TopicPtr> topics;
  topics.push_back(Message("/monocle/cameras", &monocle_msgs_msg_dds__CameraStatus__desc,
                           "monocle_msgs/msg/CameraStatus", true, 256));
  topics.push_back(Message("/monocle/calibrations", &monocle_msgs_msg_dds__Calibration__desc,
                           "monocle_msgs/msg/Calibration", true, 256));
  topics.push_back(Message("/tf", &tf2_msgs_msg_dds__TFMessage__desc, "tf2_msgs/msg/TFMessage"));
  topics.push_back(Message("/tf_static", &tf2_msgs_msg_dds__TFMessage__desc,
                           "tf2_msgs/msg/TFMessage", true, 64));
  topics.push_back(Message("/diagnostics", &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                           "diagnostic_msgs/msg/DiagnosticArray"));
  for (const std::string& ns : o.namespaces) {
    topics.push_back(Message(ns + "/corner_pose", &monocle_msgs_msg_dds__CornerPose__desc,
                             "monocle_msgs/msg/CornerPose"));
    topics.push_back(Message(ns + "/pose", &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                             "geometry_msgs/msg/PoseWithCovarianceStamped"));
    topics.push_back(Message(ns + "/camera_info", &sensor_msgs_msg_dds__CameraInfo__desc,
                             "sensor_msgs/msg/CameraInfo"));
    if (o.frames_every > 0) {
      // A few frames of slack for a slow disk; beyond that the oldest is dropped, not waited for.
      auto image = Message(ns + "/image_raw", &sensor_msgs_msg_dds__Image__desc,
                           "sensor_msgs/msg/Image", false, 8);
      image->keep_every = o.frames_every;
      topics.push_back(std::move(image));
    }
    topics.push_back(ServiceSample(ns, wire::kMeasurePoints, "monocle_msgs/srv/MeasurePoints", true,
                                   &monocle_msgs_srv_dds__MeasurePoints_Request__desc));
    topics.push_back(ServiceSample(ns, wire::kMeasurePoints, "monocle_msgs/srv/MeasurePoints",
                                   false, &monocle_msgs_srv_dds__MeasurePoints_Response__desc));
    topics.push_back(ServiceSample(ns, wire::kGetPose, "monocle_msgs/srv/GetPose", true,
                                   &monocle_msgs_srv_dds__GetPose_Request__desc));
    topics.push_back(ServiceSample(ns, wire::kGetPose, "monocle_msgs/srv/GetPose", false,
                                   &monocle_msgs_srv_dds__GetPose_Response__desc));
    topics.push_back(ServiceSample(ns, wire::kCalibrateFloor, "monocle_msgs/srv/CalibrateFloor",
                                   true, &monocle_msgs_srv_dds__CalibrateFloor_Request__desc));
    topics.push_back(ServiceSample(ns, wire::kCalibrateFloor, "monocle_msgs/srv/CalibrateFloor",
                                   false, &monocle_msgs_srv_dds__CalibrateFloor_Response__desc));
  }
  return topics;
}

}  // namespace

Result<std::unique_ptr<Recorder>> Recorder::Start(std::shared_ptr<dds::Entity> participant,
                                                  const std::string& path, RecordOptions options) {
  std::unique_ptr<Recorder> r(new Recorder);
  r->participant_ = std::move(participant);
  mcap::WriterOptions wo;
  wo.zstd = options.zstd;
  auto writer = mcap::Writer::Create(path, wo);
  if (!writer) return writer.error();
  r->writer_ = std::move(*writer);
  const dds_entity_t p = r->participant_->get();
  r->waitset_ = dds::Entity(dds_create_waitset(p));
  r->stop_condition_ = dds::Entity(dds_create_guardcondition(p));
  if (r->waitset_.get() < 0 || r->stop_condition_.get() < 0 ||
      dds_waitset_attach(r->waitset_.get(), r->stop_condition_.get(), 0) < 0) {
    return dds::DdsError("cannot create the recorder's waitset", r->waitset_.get());
  }
  std::map<std::string, uint16_t> schema_ids;
  for (TopicPtr& t : TopicsToRecord(options)) {
    t->topic = dds::Entity(dds_create_topic(p, t->type, t->dds_name.c_str(), nullptr, nullptr));
    if (t->topic.get() < 0) {
      return dds::DdsError("cannot create topic " + t->dds_name, t->topic.get());
    }
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, t->depth);
    if (t->transient_local) dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    t->reader = dds::Entity(dds_create_reader(p, t->topic.get(), qos, nullptr));
    dds_delete_qos(qos);
    if (t->reader.get() < 0) {
      // A secured client may not be allowed to read another's requests: record the rest.
      r->skipped_.push_back(t->ros_name + ": " +
                            dds::DdsError("no reader", t->reader.get()).message);
      continue;
    }
    const dds_entity_t cond = dds_create_readcondition(t->reader.get(), DDS_ANY_STATE);
    if (cond < 0 || dds_waitset_attach(r->waitset_.get(), cond, 0) < 0) {
      return dds::DdsError("cannot wait for " + t->dds_name, cond);
    }
    auto [it, added] = schema_ids.emplace(t->schema_name, 0);
    if (added) it->second = r->writer_->AddSchema(t->schema_name, "ros2msg", t->definition);
    t->channel =
        r->writer_->AddChannel(it->second, t->ros_name, "cdr",
                               {{"offered_qos_profiles", OfferedQos(t->transient_local, t->depth)},
                                {"dds_topic", t->dds_name}});
    t->stats.topic = t->ros_name;
    r->topics_.push_back(std::move(t));
  }
  r->thread_ = std::thread([rec = r.get()] { rec->Run(); });
  return r;
}

void Recorder::Run() {
  constexpr uint32_t kBatch = 16;
  while (true) {
    if (dds_waitset_wait(waitset_.get(), nullptr, 0, DDS_MSECS(200)) < 0) break;
    bool triggered = false;
    if (dds_read_guardcondition(stop_condition_.get(), &triggered) >= 0 && triggered) break;
    bool failed = false;
    for (auto& t : topics_) {
      ddsi_serdata* samples[kBatch] = {};
      dds_sample_info_t infos[kBatch];
      dds_return_t n;
      while (!failed &&
             (n = dds_takecdr(t->reader.get(), samples, kBatch, infos, DDS_ANY_STATE)) > 0) {
        const int64_t now = NowNs();
        for (dds_return_t i = 0; i < n; ++i) {
          const bool keep = infos[i].valid_data && (t->taken++ % t->keep_every) == 0;
          if (keep && !failed) {
            const uint32_t size = ddsi_serdata_size(samples[i]);
            ddsrt_iovec_t ref{};
            ddsi_serdata* held = ddsi_serdata_to_ser_ref(samples[i], 0, size, &ref);
            const Status s = writer_->Write(
                t->channel, t->sequence++, static_cast<uint64_t>(now),
                static_cast<uint64_t>(infos[i].source_timestamp),
                std::string_view(static_cast<const char*>(ref.iov_base), ref.iov_len));
            ddsi_serdata_to_ser_unref(held, &ref);
            std::lock_guard lock(mutex_);
            if (!s) {
              error_ = s.error();
              failed = true;
            } else {
              ++t->stats.messages;
              t->stats.bytes += size;
            }
          }
          ddsi_serdata_unref(samples[i]);
        }
      }
    }
    file_bytes_ = writer_->bytes_written();
    if (failed) break;
  }
}

Status Recorder::Finish() {
  if (finished_) {
    std::lock_guard lock(mutex_);
    return error_ ? Status(*error_) : Status(Ok{});
  }
  finished_ = true;
  dds_set_guardcondition(stop_condition_.get(), true);
  if (thread_.joinable()) thread_.join();
  const Status closed = writer_ ? writer_->Close() : Status(Ok{});
  if (writer_) file_bytes_ = writer_->bytes_written();
  std::lock_guard lock(mutex_);
  if (!error_ && !closed) error_ = closed.error();
  return error_ ? Status(*error_) : Status(Ok{});
}

Recorder::~Recorder() { (void)Finish(); }

std::vector<TopicStats> Recorder::stats() const {
  std::lock_guard lock(mutex_);
  std::vector<TopicStats> out;
  for (const auto& t : topics_) out.push_back(t->stats);
  return out;
}

std::optional<Error> Recorder::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

}  // namespace monocle::record
