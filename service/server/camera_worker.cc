#include "service/server/camera_worker.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <iostream>

#include "camera/aravis/reconnecting_source.h"
#include "service/pipeline/corner_pipeline.h"

namespace monocle {
namespace {

int64_t UnixNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// The corner detection is throughput work (a frame every 33 ms, some milliseconds each);
// point and pose queries are latency work. On a machine with few cores the detection would
// otherwise hold a core while a query waits for it: bench/service_bench measured a 1-point
// query's p50 at 1.16-1.30x ddsperf's with equal priority and 0.88-0.97x with the detection
// thread at nice 10. Only this thread is lowered (Linux sets nice per thread).
constexpr int kProcessingNice = 10;

void LowerThisThreadsPriority() {
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kProcessingNice) != 0)
    std::cerr << "monocled: cannot lower the detection thread's priority (" << std::strerror(errno)
              << "); queries may wait behind detection\n";
}

// Frames the camera numbered but we never received. GigE Vision 1.x ids are 16 bits and skip
// 0; a reconnect restarts them: neither counts as a loss.
uint64_t MissingBetween(uint64_t previous, uint64_t current) {
  if (current > previous && current - previous < 1000) return current - previous - 1;
  if (previous >= 65000 && previous <= 65535 && current < 1000)
    return 65535 - previous + current - 1;
  return 0;
}

}  // namespace

CameraWorker::CameraWorker(CameraSetup setup, CameraCalibration calibration,
                           OnProcessed on_processed, OnStateChange on_state_change,
                           OnFrame on_frame, OpenSource open_source,
                           OnSourceIntrinsics on_source_intrinsics)
    : setup_(std::move(setup)),
      on_processed_(std::move(on_processed)),
      on_frame_(std::move(on_frame)),
      on_state_change_(std::move(on_state_change)),
      open_source_(std::move(open_source)),
      on_source_intrinsics_(std::move(on_source_intrinsics)),
      calibration_(std::move(calibration)) {}

CameraWorker::~CameraWorker() { Stop(); }

void CameraWorker::Start() {
  acquisition_ = std::thread([this] { Acquire(); });
  pipeline_.emplace(CornerPipelineOptionsOf(setup_));
  if (setup_.corner()) processing_ = std::thread([this] { Process(); });
}

void CameraWorker::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  frame_ready_.notify_all();
  if (acquisition_.joinable()) acquisition_.join();
  if (processing_.joinable()) processing_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  status_.state = SourceState::kStopped;
}

void CameraWorker::SetState(SourceState state, const std::string& error) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Each change of state goes to the log once (a camera retried keeps its state), so a
    // camera that cannot be opened is said there as well as on the status topic.
    const bool first_error = status_.last_error.empty() && !error.empty();
    if (state != SourceState::kStreaming && (state != status_.state || first_error)) {
      std::cerr << "monocled: camera '" << setup_.id << "' " << ToString(state)
                << (error.empty() ? "" : ": " + error) << "\n";
    }
    status_.state = state;
    if (!error.empty()) {
      status_.last_error = error;
      status_.last_error_ns = UnixNowNs();
    }
  }
  frame_ready_.notify_all();  // a NextFrame waiting on a camera that failed answers now
  if (on_state_change_) on_state_change_();
}

// A device (reconnected when lost; it reports its own state), an image topic (reports its
// own state too), or a recording (it streams until its end: then the camera is stopped, as a
// device would be when unplugged for good).
Result<std::unique_ptr<FrameSource>> CameraWorker::OpenFrameSource(RecordingSource** recording) {
  const auto on_state = [this](SourceState s, const std::string& reason) { SetState(s, reason); };
  if (setup_.replay) {
    auto opened = RecordingSource::Open(setup_.replay->mcap_path, setup_.replay->recorded_namespace,
                                        setup_.replay->pace);
    if (!opened) return opened.error();
    *recording = opened->get();
    SetState(SourceState::kStreaming, "");
    return std::unique_ptr<FrameSource>(std::move(*opened));
  }
  if (open_source_) return open_source_(on_state);
  AravisOptions options = setup_.options;
  options.cancelled = [this] {
    std::lock_guard<std::mutex> lock(mutex_);
    return stop_;
  };
  return std::unique_ptr<FrameSource>(
      std::make_unique<ReconnectingSource>(std::move(options), on_state, setup_.stall_timeout));
}

// A calibration without intrinsics (an image topic's camera configured without a file) takes
// the first the source publishes (camera_info).
void CameraWorker::TakeSourceIntrinsics(const FrameSource& source) {
  CameraCalibration updated;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (HasIntrinsics(calibration_)) return;
    const auto intrinsics = source.intrinsics();
    if (!intrinsics) return;
    calibration_.intrinsics = *intrinsics;
    updated = calibration_;
  }
  std::cerr << "monocled: camera '" << setup_.id
            << "' takes its intrinsics from camera_info: " << updated.intrinsics
            << " (no covariance: 1-sigma figures exclude their uncertainty)\n";
  if (on_source_intrinsics_) on_source_intrinsics_(updated);
}

void CameraWorker::Acquire() {
  RecordingSource* recording = nullptr;
  auto opened = OpenFrameSource(&recording);
  if (!opened) {
    SetState(SourceState::kFailed, opened.error().message);
    return;
  }
  std::unique_ptr<FrameSource> source = std::move(opened).value();
  while (true) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    auto frame = source->Next(std::chrono::milliseconds(200));
    if (!frame && recording != nullptr) {
      if (recording->ended()) {
        SetState(SourceState::kStopped, frame.error().message);
        return;
      }
      if (frame.error().code == ErrorCode::kNotFound) continue;  // next frame not due yet
      SetState(SourceState::kFailed, frame.error().message);
      return;
    }
    if (!frame) {
      // The source has reported it (state kFailed, once): this thread's work is done.
      if (IsPermanentCameraError(frame.error())) return;
      continue;
    }
    TakeSourceIntrinsics(*source);
    const auto received = std::chrono::steady_clock::now();
    // Processing may hold a frame longer than the camera's ring has buffers: copy out of it.
    frame->grey = frame->grey.clone();
    frame->keepalive.reset();
    frame->camera_id = setup_.id;
    if (on_frame_) on_frame_(*frame);
    std::lock_guard<std::mutex> lock(mutex_);
    ++status_.frames;
    ++period_frames_;
    if (last_sequence_) status_.dropped += MissingBetween(*last_sequence_, frame->sequence);
    last_sequence_ = frame->sequence;
    if (grab_waiters_ > 0) {
      grabbed_ = *frame;
      ++grab_count_;
    }
    if (setup_.corner()) {
      if (latest_) ++status_.skipped;
      latest_ = std::move(*frame);
      latest_received_ = received;
    }
    frame_ready_.notify_all();
  }
}

void CameraWorker::Process() {
  LowerThisThreadsPriority();
  while (true) {
    Frame frame;
    std::chrono::steady_clock::time_point received;
    CameraCalibration calibration;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      frame_ready_.wait(lock, [&] { return stop_ || latest_.has_value(); });
      if (stop_) return;
      frame = std::move(*latest_);
      latest_.reset();
      received = latest_received_;
      calibration = calibration_;
    }
    ProcessedFrame out;
    out.sequence = frame.sequence;
    out.capture_time_ns = frame.capture_time_ns;
    out.camera_clock = frame.time_source == TimeSource::kCamera;
    if (HasIntrinsics(calibration)) {
      CornerPipelineResult result =
          pipeline_->Process(frame.grey, calibration, CaptureTimeS(frame));
      out.corner = std::move(result.corner);
      out.map = std::move(result.map);
    } else {
      out.corner =
          MakeError(ErrorCode::kNotFound, "no intrinsics yet: waiting for the camera_info beside " +
                                              setup_.options.device +
                                              " (or give the camera a calibration file)");
    }
    out.processing_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - received)
                            .count();
    if (on_processed_) on_processed_(out);
    const double latency_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - received)
            .count();
    std::lock_guard<std::mutex> lock(mutex_);
    period_latency_ms_.push_back(latency_ms);
    if (!out.corner) {
      status_.last_error = out.corner.error().message;
      status_.last_error_ns = UnixNowNs();
    }
  }
}

WorkerStatus CameraWorker::Snapshot(bool new_period) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!new_period) return status_;
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - period_start_).count();
  status_.fps = seconds > 0 ? static_cast<double>(period_frames_) / seconds : 0;
  if (!period_latency_ms_.empty()) {
    auto mid = period_latency_ms_.begin() + static_cast<long>(period_latency_ms_.size() / 2);
    std::nth_element(period_latency_ms_.begin(), mid, period_latency_ms_.end());
    status_.latency_ms = *mid;
  }
  period_latency_ms_.clear();
  period_frames_ = 0;
  period_start_ = now;
  return status_;
}

Result<Frame> CameraWorker::NextFrame(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  ++grab_waiters_;
  const uint64_t before = grab_count_;
  // A camera that has not delivered its first frame yet (a simulator still rendering, a GigE
  // camera still booting after the service started) gets longer; a failed one answers at once.
  const bool first = status_.frames == 0;
  const auto wait = first ? std::max(timeout, kFirstFrameWait) : timeout;
  frame_ready_.wait_for(lock, wait, [&] {
    return stop_ || grab_count_ > before || status_.state == SourceState::kFailed;
  });
  --grab_waiters_;
  if (grab_count_ > before && grabbed_) {
    Frame copy = *grabbed_;
    if (grab_waiters_ == 0) grabbed_.reset();
    return copy;
  }
  std::string why = "no frame from camera '" + setup_.id + "' within " +
                    std::to_string(wait.count()) + " ms" +
                    (first ? " since the service started" : "");
  if (!status_.last_error.empty()) why += " (last error: " + status_.last_error + ")";
  return MakeError(ErrorCode::kNotFound, why);
}

CameraCalibration CameraWorker::calibration() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return calibration_;
}

void CameraWorker::SetCalibration(const CameraCalibration& calibration) {
  std::lock_guard<std::mutex> lock(mutex_);
  calibration_ = calibration;
}

}  // namespace monocle
