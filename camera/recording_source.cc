#include "camera/recording_source.h"

#include <algorithm>
#include <cstring>
#include <iostream>
#include <map>
#include <set>
#include <thread>
#include <type_traits>

#include "camera/ros/image_sample.h"
#include "idl/monocle_msgs.h"
#include "idl/protocol/cdr.h"
#include "idl/ros2_messages.h"

namespace monocle {
namespace {

// MCAP channel topics are ROS names (idl/record/recorder.h).
constexpr const char* kCamerasChannel = "/monocle/cameras";
constexpr const char* kCalibrationsChannel = "/monocle/calibrations";
constexpr const char* kImageLeaf = "/image_raw";

std::string Str(const char* s) { return StringOf(s); }

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

Result<std::vector<RecordedCamera>> ListRecordedCameras(const std::string& mcap_path) {
  auto reader = mcap::Reader::Open(mcap_path);
  if (!reader) return reader.error();
  // Cameras with frames, by namespace, from the channel list (the summary).
  std::map<std::string, RecordedCamera> by_namespace;
  for (const auto& [id, ch] : reader->summary().channels) {
    if (!EndsWith(ch.topic, kImageLeaf)) continue;
    RecordedCamera& cam =
        by_namespace[ch.topic.substr(0, ch.topic.size() - std::strlen(kImageLeaf))];
    const auto count = reader->summary().channel_message_counts.find(id);
    if (count != reader->summary().channel_message_counts.end()) cam.frames += count->second;
  }
  for (auto& [ns, cam] : by_namespace) cam.ros_namespace = ns;
  std::set<std::string> need_status, need_calibration;
  for (const auto& [ns, cam] : by_namespace) {
    need_status.insert(ns);
    need_calibration.insert(ns);
  }
  Error bad = MakeError(ErrorCode::kInvalidArgument, "");
  bool failed = false;
  // The first sample of type T for each framed camera still in `need`, handed to `take`.
  auto first_per_camera = [&](const mcap::Message& m, const dds_topic_descriptor_t* type,
                              const std::string& what, std::set<std::string>& need,
                              auto take) -> bool {
    using Sample = std::remove_cvref_t<decltype(*take.sample_type)>;
    auto s = dds::DecodedSample<Sample>::Decode(type, m.data);
    if (s == nullptr) {
      bad = MakeError(ErrorCode::kInvalidArgument, mcap_path + ": a " + what);
      failed = true;
      return false;
    }
    const auto it = by_namespace.find(Str(s->get().ros_namespace));
    if (it != by_namespace.end() && need.erase(it->first) == 1) take(s->get(), it->second);
    return true;
  };
  struct TakeStatus {
    const monocle_msgs_msg_dds__CameraStatus_* sample_type = nullptr;
    void operator()(const monocle_msgs_msg_dds__CameraStatus_& s, RecordedCamera& cam) const {
      cam.id = Str(s.camera);
      cam.role = Str(s.role);
      cam.device = Str(s.device);
    }
  };
  struct TakeCalibration {
    const monocle_msgs_msg_dds__Calibration_* sample_type = nullptr;
    void operator()(const monocle_msgs_msg_dds__Calibration_& c, RecordedCamera& cam) const {
      if (cam.id.empty()) cam.id = Str(c.camera);
      cam.calibration_text = Str(c.text);
      cam.calibration_file = Str(c.file);
      if (c.has_ceiling) cam.ceiling_distance_m = c.ceiling_distance_m;
    }
  };
  const Status walked =
      reader->ForEachMessage([&](const mcap::ChannelInfo& ch, const mcap::Message& m) {
        if (ch.topic == kCamerasChannel &&
            !first_per_camera(m, &monocle_msgs_msg_dds__CameraStatus__desc,
                              "/monocle/cameras message is not a CameraStatus", need_status,
                              TakeStatus{})) {
          return false;
        }
        if (ch.topic == kCalibrationsChannel &&
            !first_per_camera(m, &monocle_msgs_msg_dds__Calibration__desc,
                              "/monocle/calibrations message is not a Calibration",
                              need_calibration, TakeCalibration{})) {
          return false;
        }
        return !need_status.empty() || !need_calibration.empty();
      });
  if (failed) return bad;
  if (!walked) return walked.error();
  std::vector<RecordedCamera> out;
  for (auto& [ns, cam] : by_namespace) {
    if (cam.id.empty()) cam.id = ns.substr(ns.find_last_of('/') + 1);
    out.push_back(std::move(cam));
  }
  return out;
}

Result<std::unique_ptr<RecordingSource>> RecordingSource::Open(const std::string& mcap_path,
                                                               const std::string& ros_namespace,
                                                               ReplayPace pace) {
  if (!(pace.rate >= 0) || pace.rate > 1000) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "replay rate must be 0 (no waiting) or a factor up to 1000");
  }
  std::unique_ptr<RecordingSource> s(new RecordingSource());
  s->path_ = mcap_path;
  s->topic_ = ros_namespace + kImageLeaf;
  s->id_ = mcap_path + ":" + s->topic_;
  s->pace_ = pace;
  if (Status r = s->Rewind(); !r) return r.error();
  bool has_channel = false;
  for (const auto& [id, ch] : s->reader_->summary().channels) has_channel |= ch.topic == s->topic_;
  if (!has_channel) {
    return MakeError(ErrorCode::kNotFound, mcap_path + " has no frames of " + ros_namespace +
                                               " (no " + s->topic_ +
                                               " channel; record with --frames every or N)");
  }
  return s;
}

Status RecordingSource::Rewind() {
  stream_.reset();
  auto reader = mcap::Reader::Open(path_);
  if (!reader) return reader.error();
  reader_ = std::make_unique<mcap::Reader>(std::move(*reader));
  // A damaged chunk costs its frames, not the replay: skipped with a warning.
  stream_ = std::make_unique<mcap::Reader::MessageStream>(
      reader_->Messages(/*skip_damaged_chunks=*/true));
  chunks_warned_ = 0;
  first_stamp_ns_.reset();
  return Ok{};
}

void RecordingSource::WarnOfSkippedChunks() {
  const auto& skipped = stream_->skipped();
  for (; chunks_warned_ < skipped.size(); ++chunks_warned_) {
    std::cerr << "monocle: warning: " << path_ << ": skipped a damaged chunk at byte "
              << skipped[chunks_warned_].offset << " (" << skipped[chunks_warned_].why
              << "); the frames in it are missing\n";
  }
}

Result<std::optional<Frame>> RecordingSource::ReadNext() {
  while (true) {
    auto m = stream_->Next();
    WarnOfSkippedChunks();
    if (!m) return m.error();
    if (!*m) return std::optional<Frame>();
    if (stream_->channel((*m)->channel_id).topic != topic_) continue;
    auto image = dds::DecodedSample<sensor_msgs_msg_dds__Image_>::Decode(
        &sensor_msgs_msg_dds__Image__desc, (*m)->data);
    const std::string where = path_ + ": " + topic_ + " frame " + std::to_string(sequence_);
    if (image == nullptr) {
      return MakeError(ErrorCode::kInvalidArgument, where + " is not a sensor_msgs/Image");
    }
    const auto& img = image->get();
    auto grey = GreyOfRosImage(ViewOf(img));  // our own copy: `image` is freed on return
    if (!grey) return MakeError(ErrorCode::kInvalidArgument, where + ": " + grey.error().message);
    Frame frame;
    frame.grey = std::move(grey).value();
    frame.frame_id = StringOf(img.header.frame_id);
    frame.capture_time_ns = StampNs(img.header.stamp);
    frame.time_source = TimeSource::kHost;
    return std::optional<Frame>(std::move(frame));
  }
}

Result<Frame> RecordingSource::Next(std::chrono::milliseconds timeout) {
  if (!pending_) {
    auto next = ReadNext();
    if (!next) return next.error();
    if (!*next && pace_.loop && sequence_ > 0) {
      if (Status r = Rewind(); !r) return r.error();
      next = ReadNext();
      if (!next) return next.error();
    }
    if (!*next) {
      ended_ = true;
      return MakeError(ErrorCode::kNotFound, "end of the recording " + path_ + " after " +
                                                 std::to_string(sequence_) + " frames of " +
                                                 topic_);
    }
    pending_stamp_ns_ = (*next)->capture_time_ns;
    pending_ = std::move(**next);
  }
  if (pace_.rate > 0) {
    const auto now = std::chrono::steady_clock::now();
    if (!first_stamp_ns_) {
      first_stamp_ns_ = pending_stamp_ns_;
      first_wall_ = now;
    }
    // Frames keep their recorded spacing, divided by the rate; a stamp that goes back
    // (clock step on the robot) is not waited for.
    const auto due =
        first_wall_ +
        std::chrono::nanoseconds(static_cast<int64_t>(
            static_cast<double>(std::max<int64_t>(0, pending_stamp_ns_ - *first_stamp_ns_)) /
            pace_.rate));
    if (due > now) {
      if (due - now > timeout) {
        std::this_thread::sleep_for(timeout);
        return MakeError(ErrorCode::kNotFound, "next recorded frame not due yet");
      }
      std::this_thread::sleep_until(due);
    }
  }
  Frame out = std::move(*pending_);
  pending_.reset();
  out.sequence = sequence_++;
  return out;
}

}  // namespace monocle
