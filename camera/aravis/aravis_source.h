// Frames from a GenICam camera (GigE Vision or USB3 Vision) through Aravis.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camera/aravis/aravis_options.h"
#include "camera/aravis/glib_handles.h"
#include "camera/frame_source.h"

namespace monocle {

// A camera as Aravis lists it.
struct CameraInfo {
  std::string id, vendor, model, serial, address, protocol;
};

std::vector<CameraInfo> ListCameras();

// Aravis 0.8 cannot set up two cameras at once in one process: its device list is global,
// and two GenICam descriptions parsed on two threads corrupt each other (two "sim-floor"
// cameras opened together: "arv_dom_node_append_child: self is not a ArvDomNode", an empty
// pixel format list, a crash in g_hash_table_lookup; AravisGigeTest.TwoCamerasOpenAtOnce).
// Listing, opening and configuring a camera (real, fake or simulated GigE) hold this lock:
// cameras are set up one at a time and stream in parallel.
std::mutex& AravisSetupMutex();

class AravisSource : public FrameSource {
 public:
  // Opens, configures (every value range-checked against the device) and starts streaming.
  // The ids "sim-corner" and "sim-floor" open in-process simulated cameras (Aravis's fake
  // device, filled with rendered scenes; `SimulatedScenes()` gives their ground truth).
  static Result<std::unique_ptr<AravisSource>> Open(const AravisOptions& options);
  ~AravisSource() override;

  const std::string& id() const override { return id_; }
  Result<Frame> Next(std::chrono::milliseconds timeout) override;
  bool lost() const { return state_->lost.load(); }
  // The caller saw the stream stall: treat the camera as gone (no stop command on close).
  void MarkUnresponsive() { state_->lost.store(true); }
  uint64_t dropped() const { return dropped_; }
  const CameraInfo& info() const { return info_; }
  // Ground truth of an in-process simulated camera; null for a real one.
  const class SimScenes* SimulatedScenes() const { return scenes_.get(); }

 private:
  // Shared with the control-lost signal handler and with frames still held by the pipeline.
  struct State {
    std::atomic<bool> lost{false};
  };
  AravisSource() = default;
  static Result<std::unique_ptr<AravisSource>> Start(std::unique_ptr<AravisSource> src,
                                                     const AravisOptions& options);

  std::string id_;
  CameraInfo info_;
  std::shared_ptr<class SimScenes> scenes_;  // in-process simulation: outlives the device
  GObjectPtr<ArvDevice> fake_device_;
  GObjectPtr<ArvCamera> camera_;
  std::shared_ptr<GObjectPtr<ArvStream>> stream_;
  std::shared_ptr<State> state_ = std::make_shared<State>();
  gulong lost_handler_ = 0;
  uint64_t dropped_ = 0;
  size_t payload_ = 0;  // bytes per buffer
  bool ptp_ = false;    // camera clock synchronised by PTP (IEEE 1588)
};

}  // namespace monocle
