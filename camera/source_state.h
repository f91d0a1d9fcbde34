// The state of a frame source as the camera layer sees it. The daemon maps it onto the wire's
// CameraState (idl/protocol/values.h) in one place (service/server/wire_values.cc), so the
// camera layer needs nothing of the wire to say how its camera is.
#pragma once

#include <cstdint>

namespace monocle {

// kReconnecting: not streaming but retried (camera not found yet, lost, stalled). kFailed: a
// permanent error, reported once and not retried. kStopped: asked to stop.
enum class SourceState : uint8_t { kStreaming, kReconnecting, kStopped, kFailed };

inline const char* ToString(SourceState state) {
  switch (state) {
    case SourceState::kStreaming:
      return "streaming";
    case SourceState::kReconnecting:
      return "reconnecting";
    case SourceState::kStopped:
      return "stopped";
    case SourceState::kFailed:
      return "failed";
  }
  return "unknown";
}

}  // namespace monocle
