// Frames from an MCAP recording (`monocle record --frames ...`, `monocled --record ...
// --record-frames ...`), for replay: a camera's `<namespace>/image_raw` messages in file order,
// paced like the recording or as fast as they are taken. Also what a recording says about its
// cameras (id, role, calibration), so a replay needs nothing but the file.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/frame_source.h"
#include "service/io/mcap_reader.h"

namespace monocle {

// A camera as a recording saw it.
struct RecordedCamera {
  std::string id;             // e.g. sim-corner
  std::string ros_namespace;  // e.g. /monocle/sim_corner
  std::string role;           // "corner", "floor", "corner+floor" (from /monocle/cameras)
  std::string device;         // what the recording service opened (Aravis id, sim-*)
  // The calibration file's text as the service published it when the recording started
  // (/monocle/calibrations), and where that file was on the service's machine.
  std::string calibration_text;
  std::string calibration_file;
  // The ceiling distance the service used (the file's, or its configuration's override).
  std::optional<double> ceiling_distance_m;
  uint64_t frames = 0;  // image_raw messages in the file
};

// The cameras a recording has frames of, in namespace order. A camera needs its
// /monocle/calibrations sample to be replayed; one without is listed with empty
// calibration_text. Stops reading once every framed camera's status and calibration were
// seen (they are published at the start and kept for late joiners).
Result<std::vector<RecordedCamera>> ListRecordedCameras(const std::string& mcap_path);

struct ReplayPace {
  // 1: as recorded; 2: twice as fast; 0: no waiting (every frame as soon as it is taken).
  double rate = 1;
  bool loop = false;  // start again at the end
};

class RecordingSource : public FrameSource {
 public:
  // The frames of the camera whose topics live under `ros_namespace`.
  static Result<std::unique_ptr<RecordingSource>> Open(const std::string& mcap_path,
                                                       const std::string& ros_namespace,
                                                       ReplayPace pace);

  const std::string& id() const override { return id_; }
  // The next frame: sequence = its index in the recording (from 0, counting on across
  // loops), capture time = the recorded header stamp. kNotFound while the next frame is not
  // due yet (within `timeout`) and at the end (then ended() is true); kInvalidArgument for a
  // frame that is not mono8 or not consistent (the file is from elsewhere).
  Result<Frame> Next(std::chrono::milliseconds timeout) override;
  bool ended() const { return ended_; }
  uint64_t frames_read() const { return sequence_; }

 private:
  RecordingSource() = default;
  Status Rewind();
  // The next image_raw message of our channel, decoded; nullopt at the end of the file.
  Result<std::optional<Frame>> ReadNext();
  void WarnOfSkippedChunks();  // each damaged chunk passed over, once

  std::string id_, path_, topic_;
  ReplayPace pace_;
  std::unique_ptr<mcap::Reader> reader_;
  std::unique_ptr<mcap::Reader::MessageStream> stream_;
  size_t chunks_warned_ = 0;
  std::optional<Frame> pending_;  // read, not yet due
  int64_t pending_stamp_ns_ = 0;
  // Pacing: recorded stamp of the first frame of this pass, and when it was handed out.
  std::optional<int64_t> first_stamp_ns_;
  std::chrono::steady_clock::time_point first_wall_;
  uint64_t sequence_ = 0;
  bool ended_ = false;
};

}  // namespace monocle
