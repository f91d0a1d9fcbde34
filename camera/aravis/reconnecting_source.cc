#include "camera/aravis/reconnecting_source.h"

#include <algorithm>
#include <thread>

namespace monocle {

ReconnectingSource::ReconnectingSource(AravisOptions options, StateCallback on_state,
                                       std::chrono::milliseconds stall_timeout)
    : options_(std::move(options)), on_state_(std::move(on_state)), stall_timeout_(stall_timeout) {}

void ReconnectingSource::SetState(SourceState s, const std::string& reason) {
  if (s == state_ && s == SourceState::kStreaming) return;
  state_ = s;
  if (on_state_) on_state_(s, reason);
}

Result<Frame> ReconnectingSource::Next(std::chrono::milliseconds timeout) {
  if (failed_) return *failed_;  // permanent: reported once, never retried
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!source_) {
      const auto now = std::chrono::steady_clock::now();
      if (now < next_attempt_) {
        std::this_thread::sleep_for(
            std::min<std::chrono::steady_clock::duration>(next_attempt_ - now, deadline - now));
        continue;
      }
      auto opened = AravisSource::Open(options_);
      if (!opened) {
        // Asked to stop while opening: nothing to report, the caller is going away.
        if (opened.error().code == ErrorCode::kCancelled) return opened.error();
        if (IsPermanentCameraError(opened.error())) {
          failed_ = opened.error();
          SetState(SourceState::kFailed, opened.error().message);
          return opened.error();
        }
        // Back-off doubles up to 0.5 s: a camera that answers again streams within a second
        // however long it was away (issue 14), for one discovery packet per attempt.
        next_attempt_ = std::chrono::steady_clock::now() + backoff_;
        backoff_ = std::min(backoff_ * 2, kMaxBackoff);
        // Say why, so a status display can tell "camera not found" from "lost".
        SetState(SourceState::kReconnecting, opened.error().message);
        continue;
      }
      source_ = std::move(opened).value();
      backoff_ = std::chrono::milliseconds(100);
      last_frame_ = std::chrono::steady_clock::now();
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    auto frame = source_->Next(std::min(left, stall_timeout_));
    if (frame) {
      last_frame_ = std::chrono::steady_clock::now();
      SetState(SourceState::kStreaming, "");
      return frame;
    }
    // Lost (control-lost) or no frame for longer than the stall timeout: report, drop, retry.
    const bool stalled = std::chrono::steady_clock::now() - last_frame_ >= stall_timeout_;
    if (frame.error().code == ErrorCode::kIo || stalled) {
      // Report first: closing a camera that no longer answers can take seconds of GVCP
      // time-outs.
      SetState(SourceState::kReconnecting, stalled && frame.error().code != ErrorCode::kIo
                                               ? "camera '" + options_.device +
                                                     "' stalled: no frame for " +
                                                     std::to_string(stall_timeout_.count()) + " ms"
                                               : frame.error().message);
      source_->MarkUnresponsive();
      // Aravis's teardown of a camera that vanished blocks for seconds (GVCP time-outs):
      // close it on a thread of its own so acquisition goes straight back to reconnecting.
      std::thread([lost = std::move(source_)]() mutable { lost.reset(); }).detach();
      next_attempt_ = std::chrono::steady_clock::now() + backoff_;
    }
  }
  return MakeError(ErrorCode::kNotFound,
                   "no frame from camera '" + options_.device + "' yet (" +
                       (state_ == SourceState::kStreaming ? "streaming" : "reconnecting") + ")");
}

}  // namespace monocle
