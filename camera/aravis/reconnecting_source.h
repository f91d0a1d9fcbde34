// An Aravis camera that survives losing its camera: on control-lost or a stalled stream it
// reports the loss at once, then reopens the same camera with back-off and resumes,
// without restarting the process.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "camera/aravis/aravis_source.h"
#include "camera/source_state.h"

namespace monocle {

class ReconnectingSource : public FrameSource {
 public:
  using StateCallback = std::function<void(SourceState, const std::string& reason)>;

  ReconnectingSource(AravisOptions options, StateCallback on_state,
                     std::chrono::milliseconds stall_timeout = std::chrono::milliseconds(1000));

  const std::string& id() const override { return options_.device; }
  // A frame, or the error of this attempt (loss, waiting for the camera); keep calling. A
  // permanent error (IsPermanentCameraError) puts the source in kFailed for good: every
  // later call returns that error at once.
  Result<Frame> Next(std::chrono::milliseconds timeout) override;
  SourceState state() const { return state_; }
  static constexpr std::chrono::milliseconds kMaxBackoff{500};

 private:
  void SetState(SourceState s, const std::string& reason);

  AravisOptions options_;
  StateCallback on_state_;
  std::chrono::milliseconds stall_timeout_;
  std::unique_ptr<AravisSource> source_;
  std::optional<Error> failed_;
  SourceState state_ = SourceState::kReconnecting;
  std::chrono::milliseconds backoff_{100};
  std::chrono::steady_clock::time_point next_attempt_{};
  std::chrono::steady_clock::time_point last_frame_{};
};

}  // namespace monocle
