// One camera of the service: an acquisition thread that never waits for processing, and (for
// a corner camera) a processing thread that locates the corner in the latest frame. Keeps the
// camera's health figures for the status topic. DDS-free: results go to a callback.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "camera/frame_source.h"
#include "camera/source_state.h"
#include "idl/protocol/values.h"
#include "service/geometry/map_pose_tracker.h"
#include "service/io/calibration_file.h"
#include "service/pipeline/corner_pipeline.h"
#include "service/server/service_config.h"

namespace monocle {

class RecordingSource;

// One processed frame of a corner camera.
struct ProcessedFrame {
  uint64_t sequence = 0;
  int64_t capture_time_ns = 0;
  bool camera_clock = false;
  Result<CornerLocation> corner = MakeError(ErrorCode::kNotFound, "not processed");
  std::optional<MapLocation> map;  // with a room map and a corner pose: where in the map
  int64_t processing_ns = 0;       // frame received -> pose computed
};

struct WorkerStatus {
  SourceState state = SourceState::kReconnecting;
  double fps = 0;         // frames received per second since the last snapshot
  uint64_t frames = 0;    // since start
  uint64_t dropped = 0;   // frame id gaps: sent by the camera, never received
  uint64_t skipped = 0;   // not processed because processing was still busy
  double latency_ms = 0;  // median, frame received -> result handed on, since last snapshot
  std::string last_error;
  int64_t last_error_ns = 0;  // Unix time
};

class CameraWorker {
 public:
  // Called on the processing thread after each corner frame.
  using OnProcessed = std::function<void(const ProcessedFrame&)>;
  // Called when the camera's state changes (lost, back, stopped).
  using OnStateChange = std::function<void()>;
  // Called on the acquisition thread with every frame received (its own copy of the pixels).
  using OnFrame = std::function<void(const Frame&)>;
  // Opens a source that is not an Aravis camera (an image topic); it reports its own state.
  using StateCallback = std::function<void(SourceState, const std::string& reason)>;
  using OpenSource = std::function<Result<std::unique_ptr<FrameSource>>(StateCallback)>;

  // Called once when a calibration without intrinsics takes the source's own (camera_info).
  using OnSourceIntrinsics = std::function<void(const CameraCalibration&)>;

  // Frames come from `open_source` if given, else from the Aravis device of `setup`.
  CameraWorker(CameraSetup setup, CameraCalibration calibration, OnProcessed on_processed,
               OnStateChange on_state_change, OnFrame on_frame = {}, OpenSource open_source = {},
               OnSourceIntrinsics on_source_intrinsics = {});
  ~CameraWorker();
  CameraWorker(const CameraWorker&) = delete;
  CameraWorker& operator=(const CameraWorker&) = delete;

  void Start();
  void Stop();  // joins the threads

  const CameraSetup& setup() const { return setup_; }
  // The health figures; `new_period` starts a new averaging period for fps and latency.
  WorkerStatus Snapshot(bool new_period);
  // A copy of the first frame received after this call, waiting at most `timeout` (or
  // kFirstFrameWait while the camera has not delivered any frame yet).
  Result<Frame> NextFrame(std::chrono::milliseconds timeout);
  static constexpr std::chrono::milliseconds kFirstFrameWait{20000};
  CameraCalibration calibration() const;
  void SetCalibration(const CameraCalibration& calibration);

 private:
  void Acquire();
  Result<std::unique_ptr<FrameSource>> OpenFrameSource(RecordingSource** recording);
  void TakeSourceIntrinsics(const FrameSource& source);
  void Process();
  void SetState(SourceState state, const std::string& error);

  const CameraSetup setup_;
  const OnProcessed on_processed_;
  const OnFrame on_frame_;
  const OnStateChange on_state_change_;
  const OpenSource open_source_;
  const OnSourceIntrinsics on_source_intrinsics_;

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable frame_ready_;
  bool stop_ = false;
  std::optional<Frame> latest_;  // for processing; a newer frame replaces one not yet taken
  std::chrono::steady_clock::time_point latest_received_;
  std::optional<Frame> grabbed_;  // for NextFrame
  uint64_t grab_count_ = 0;
  int grab_waiters_ = 0;
  CameraCalibration calibration_;
  WorkerStatus status_;
  uint64_t period_frames_ = 0;
  std::chrono::steady_clock::time_point period_start_ = std::chrono::steady_clock::now();
  std::vector<double> period_latency_ms_;
  std::optional<uint64_t> last_sequence_;

  // Owned by the processing thread alone (not guarded).
  std::optional<CornerPipeline> pipeline_;

  std::thread acquisition_, processing_;
};

}  // namespace monocle
