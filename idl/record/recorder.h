// Records what monocle publishes on DDS into an MCAP file (service/io/mcap_writer.h): per
// camera its corner poses, poses, camera info, frames (all, every Nth or none) and the
// requests and replies of its three services; for all cameras /monocle/cameras,
// /monocle/calibrations, /tf, /tf_static and /diagnostics. Messages are stored as they
// travelled (CDR, taken from Cyclone DDS without decoding), with their ROS 2 message
// definitions as schemas, so Foxglove and `ros2 bag` read the file.
//
// The recorder is an ordinary DDS subscriber with keep-last readers on its own thread: in
// `monocle record` on its own participant, in `monocled --record` on the service's. A slow
// disk costs the recorder samples (counted as lost), never the publisher's time.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "idl/protocol/dds.h"
#include "service/io/mcap_writer.h"

namespace monocle::record {

struct RecordOptions {
  std::vector<std::string> namespaces;  // cameras' ROS namespaces, e.g. /monocle/sim_corner
  // Frames (image_raw): 0 none, 1 every frame, N every Nth frame received.
  int frames_every = 0;
  bool zstd = false;  // compress chunks losslessly (zstd)
};

// One topic being recorded.
struct TopicStats {
  std::string topic;  // ROS name, as in the file
  uint64_t messages = 0;
  uint64_t bytes = 0;
};

class Recorder {
 public:
  // Creates the file and the readers, and starts recording.
  static Result<std::unique_ptr<Recorder>> Start(std::shared_ptr<dds::Entity> participant,
                                                 const std::string& path, RecordOptions options);
  ~Recorder();  // Finish() if not called
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Stops taking samples, writes the summary and closes the file. Returns the first error
  // (a full disk stops the recording early; the file then holds everything up to it).
  Status Finish();

  // Thread-safe snapshots for progress displays.
  std::vector<TopicStats> stats() const;
  uint64_t file_bytes() const { return file_bytes_.load(); }
  // Set when writing failed (the recording has stopped); the file is still closed properly.
  std::optional<Error> error() const;
  // Topics that could not be subscribed (DDS Security permissions), with the reason.
  const std::vector<std::string>& skipped() const { return skipped_; }

  struct Topic;  // one recorded topic: its reader and channel (recorder.cc)

 private:
  Recorder() = default;
  void Run();

  std::shared_ptr<dds::Entity> participant_;
  std::unique_ptr<mcap::Writer> writer_;
  std::vector<std::unique_ptr<Topic>> topics_;
  std::vector<std::string> skipped_;
  dds::Entity waitset_;
  dds::Entity stop_condition_;
  std::thread thread_;
  bool finished_ = false;
  mutable std::mutex mutex_;  // stats and error
  std::optional<Error> error_;
  std::atomic<uint64_t> file_bytes_{0};
};

}  // namespace monocle::record
