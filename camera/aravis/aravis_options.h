// What a camera is opened with: device and GenICam settings. Free of <arv.h> so that the
// configuration and everything that reads it need not see Aravis or GLib.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace monocle {

// Device ids that open in-process simulated cameras (Aravis's fake device filled with rendered
// scenes) instead of hardware: a ceiling corner, the same in a white-painted room, a floor.
inline constexpr std::array<const char*, 3> kBuiltInSimulatedCameras = {
    "sim-corner", "sim-corner-realistic", "sim-floor"};

struct AravisOptions {
  std::string device;  // Aravis device id, IPv4 address or serial number
  std::string pixel_format = "Mono8";
  std::optional<std::array<int, 4>> region;  // x, y, width, height in pixels
  std::optional<double> exposure_us;
  std::optional<double> gain;
  std::optional<double> frame_rate_hz;
  std::optional<int> packet_size_bytes;         // GigE only
  std::optional<int> inter_packet_delay_ticks;  // GigE only
  // Any other GenICam feature by name, value as text; checked against the device.
  std::vector<std::pair<std::string, std::string>> features;
  int buffers = 4;  // ring handed to the pipeline without copying
  // True once the caller has been asked to stop: an open that takes long (a simulated camera
  // rendering its frames, seconds under a sanitizer) gives up between its steps with
  // kCancelled, so a service stops promptly at every stage.
  std::function<bool()> cancelled;
};

}  // namespace monocle
