#include "camera/aravis/aravis_source.h"

#include "camera/aravis/tsan_handoff.h"
#include "camera/sim/sim_gv_camera.h"

#include <arpa/inet.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace monocle {

namespace {
// Gives a buffer back to the stream for the camera to fill again (tsan_handoff.h).
void Requeue(ArvStream* stream, ArvBuffer* buffer) {
  BufferHandedOver(buffer);
  arv_stream_push_buffer(stream, buffer);
}
}  // namespace
namespace {

Error Fail(ErrorCode code, const std::string& message) { return MakeError(code, message); }

bool LooksLikeIpv4(const std::string& s) {
  in_addr addr{};
  return inet_pton(AF_INET, s.c_str(), &addr) == 1;
}

std::string Join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// Device id for an id, IPv4 address or serial number. Call with AravisSetupMutex held.
std::optional<std::string> ResolveDevice(const std::string& name) {
  if (LooksLikeIpv4(name)) return name;  // Aravis opens GigE cameras by address directly
  arv_update_device_list();
  const unsigned n = arv_get_n_devices();
  for (unsigned i = 0; i < n; ++i) {
    const char* id = arv_get_device_id(i);
    const char* serial = arv_get_device_serial_nbr(i);
    if ((id != nullptr && name == id) || (serial != nullptr && name == serial))
      return std::string(id);
  }
  return std::nullopt;
}

Status CheckRange(const std::string& what, double value, double lo, double hi, const char* unit) {
  if (value < lo || value > hi) {
    std::ostringstream os;
    os << what << " " << value << " " << unit << " is out of the camera's range [" << lo << ", "
       << hi << "] " << unit;
    return Fail(ErrorCode::kOutOfRange, os.str());
  }
  return Ok{};
}

Status SetFeature(ArvCamera* camera, const std::string& name, const std::string& value) {
  ArvGcNode* node = arv_device_get_feature(arv_camera_get_device(camera), name.c_str());
  if (node == nullptr) {
    // A configuration error (IsPermanentCameraError), not a camera still to be found.
    return Fail(ErrorCode::kInvalidArgument,
                "unknown GenICam feature '" + name + "' on this camera");
  }
  GErrorSlot err;
  if (ARV_IS_GC_FLOAT(node) || ARV_IS_GC_INTEGER(node)) {
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0' || !std::isfinite(v)) {
      return Fail(ErrorCode::kInvalidArgument,
                  "feature '" + name + "' needs a number, not '" + value + "'");
    }
    if (ARV_IS_GC_FLOAT(node)) {
      double lo = 0, hi = 0;
      arv_camera_get_float_bounds(camera, name.c_str(), &lo, &hi, err.out());
      if (auto s = CheckRange("feature '" + name + "' value", v, lo, hi, ""); !s) return s;
      arv_camera_set_float(camera, name.c_str(), v, err.out());
    } else {
      gint64 lo = 0, hi = 0;
      arv_camera_get_integer_bounds(camera, name.c_str(), &lo, &hi, err.out());
      if (auto s = CheckRange("feature '" + name + "' value", v, static_cast<double>(lo),
                              static_cast<double>(hi), "");
          !s) {
        return s;
      }
      arv_camera_set_integer(camera, name.c_str(), static_cast<gint64>(std::llround(v)), err.out());
    }
  } else if (ARV_IS_GC_ENUMERATION(node)) {
    guint n = 0;
    const char** values =
        arv_camera_dup_available_enumerations_as_strings(camera, name.c_str(), &n, err.out());
    std::vector<std::string> allowed;
    for (guint i = 0; values != nullptr && i < n; ++i) allowed.emplace_back(values[i]);
    g_free(values);
    if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
      return Fail(ErrorCode::kOutOfRange, "feature '" + name + "' cannot be '" + value +
                                              "' (the camera offers: " + Join(allowed) + ")");
    }
    arv_camera_set_string(camera, name.c_str(), value.c_str(), err.out());
  } else if (ARV_IS_GC_BOOLEAN(node)) {
    if (value != "true" && value != "false") {
      return Fail(ErrorCode::kInvalidArgument,
                  "feature '" + name + "' needs true or false, not '" + value + "'");
    }
    arv_camera_set_boolean(camera, name.c_str(), value == "true", err.out());
  } else {
    arv_camera_set_string(camera, name.c_str(), value.c_str(), err.out());
  }
  if (err.failed())
    return Fail(ErrorCode::kIo, "cannot set feature '" + name + "': " + err.message());
  return Ok{};
}

Status Configure(ArvCamera* camera, const AravisOptions& o) {
  GErrorSlot err;
  {
    guint n = 0;
    const char** formats = arv_camera_dup_available_pixel_formats_as_strings(camera, &n, err.out());
    // A camera that could not be asked is not a camera without the format: retried.
    if (err.failed()) {
      g_free(formats);
      return Fail(ErrorCode::kIo, "cannot read the camera's pixel formats: " + err.message());
    }
    std::vector<std::string> offered;
    for (guint i = 0; formats != nullptr && i < n; ++i) offered.emplace_back(formats[i]);
    g_free(formats);
    static const std::vector<std::string> kSupported{
        "Mono8",    "Mono16", "BayerRG8",   "BayerGR8", "BayerGB8",
        "BayerBG8", "RGB8",   "RGB8Packed", "BGR8",     "BGR8Packed"};
    if (std::find(kSupported.begin(), kSupported.end(), o.pixel_format) == kSupported.end()) {
      return Fail(ErrorCode::kInvalidArgument, "unsupported pixel format '" + o.pixel_format +
                                                   "' (monocle reads: " + Join(kSupported) + ")");
    }
    if (std::find(offered.begin(), offered.end(), o.pixel_format) == offered.end()) {
      return Fail(ErrorCode::kOutOfRange, "the camera does not offer pixel format '" +
                                              o.pixel_format + "' (it offers: " + Join(offered) +
                                              ")");
    }
    arv_camera_set_pixel_format_from_string(camera, o.pixel_format.c_str(), err.out());
    if (err.failed()) return Fail(ErrorCode::kIo, "cannot set pixel format: " + err.message());
  }
  if (o.region) {
    const auto [x, y, w, h] = *o.region;
    gint wmin = 0, wmax = 0, hmin = 0, hmax = 0;
    arv_camera_get_width_bounds(camera, &wmin, &wmax, err.out());
    arv_camera_get_height_bounds(camera, &hmin, &hmax, err.out());
    if (auto s = CheckRange("region width", w, wmin, wmax, "px"); !s) return s;
    if (auto s = CheckRange("region height", h, hmin, hmax, "px"); !s) return s;
    arv_camera_set_region(camera, x, y, w, h, err.out());
    if (err.failed()) return Fail(ErrorCode::kIo, "cannot set region: " + err.message());
  }
  if (o.exposure_us) {
    double lo = 0, hi = 0;
    arv_camera_get_exposure_time_bounds(camera, &lo, &hi, err.out());
    if (auto s = CheckRange("exposure", *o.exposure_us, lo, hi, "us"); !s) return s;
    arv_camera_set_exposure_time(camera, *o.exposure_us, err.out());
    if (err.failed()) return Fail(ErrorCode::kIo, "cannot set exposure: " + err.message());
  }
  if (o.gain) {
    double lo = 0, hi = 0;
    arv_camera_get_gain_bounds(camera, &lo, &hi, err.out());
    if (auto s = CheckRange("gain", *o.gain, lo, hi, "dB"); !s) return s;
    arv_camera_set_gain(camera, *o.gain, err.out());
    if (err.failed()) return Fail(ErrorCode::kIo, "cannot set gain: " + err.message());
  }
  if (o.frame_rate_hz) {
    double lo = 0, hi = 0;
    arv_camera_get_frame_rate_bounds(camera, &lo, &hi, err.out());
    if (auto s = CheckRange("frame rate", *o.frame_rate_hz, lo, hi, "Hz"); !s) return s;
    arv_camera_set_frame_rate(camera, *o.frame_rate_hz, err.out());
    if (err.failed()) return Fail(ErrorCode::kIo, "cannot set frame rate: " + err.message());
  }
  if (arv_camera_is_gv_device(camera)) {
    if (o.packet_size_bytes) {
      arv_camera_gv_set_packet_size(camera, *o.packet_size_bytes, err.out());
      if (err.failed())
        return Fail(ErrorCode::kOutOfRange, "cannot set packet size: " + err.message());
    }
    if (o.inter_packet_delay_ticks) {
      arv_camera_gv_set_packet_delay(camera, *o.inter_packet_delay_ticks, err.out());
      if (err.failed())
        return Fail(ErrorCode::kOutOfRange, "cannot set inter-packet delay: " + err.message());
    }
  }
  for (const auto& [name, value] : o.features) {
    if (auto s = SetFeature(camera, name, value); !s) return s;
  }
  return Ok{};
}

// 8-bit grey from a buffer: a view on Mono8 data (no copy), converted otherwise.
std::optional<cv::Mat> GreyView(ArvBuffer* buffer, size_t allocated) {
  size_t size = 0;
  const void* data = arv_buffer_get_image_data(buffer, &size);
  // Aravis's in-process fake stream does not record a received size when a custom fill
  // pattern runs: the buffer then holds a whole payload.
  if (size == 0) size = allocated;
  const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
  const ArvPixelFormat format = arv_buffer_get_image_pixel_format(buffer);
  auto* bytes = static_cast<uint8_t*>(const_cast<void*>(data));
  auto need = [&](size_t bpp) { return size >= static_cast<size_t>(w) * h * bpp; };
  cv::Mat out;
  switch (format) {
    case ARV_PIXEL_FORMAT_MONO_8:
      if (!need(1)) return std::nullopt;
      return cv::Mat(h, w, CV_8UC1, bytes);
    case ARV_PIXEL_FORMAT_MONO_16:
      if (!need(2)) return std::nullopt;
      cv::Mat(h, w, CV_16UC1, bytes).convertTo(out, CV_8U, 1.0 / 256);
      return out;
    case ARV_PIXEL_FORMAT_BAYER_RG_8:
    case ARV_PIXEL_FORMAT_BAYER_GR_8:
    case ARV_PIXEL_FORMAT_BAYER_GB_8:
    case ARV_PIXEL_FORMAT_BAYER_BG_8: {
      if (!need(1)) return std::nullopt;
      // OpenCV names Bayer patterns by the second row's first two pixels.
      const int code = format == ARV_PIXEL_FORMAT_BAYER_RG_8   ? cv::COLOR_BayerBG2GRAY
                       : format == ARV_PIXEL_FORMAT_BAYER_GR_8 ? cv::COLOR_BayerGB2GRAY
                       : format == ARV_PIXEL_FORMAT_BAYER_GB_8 ? cv::COLOR_BayerGR2GRAY
                                                               : cv::COLOR_BayerRG2GRAY;
      cv::cvtColor(cv::Mat(h, w, CV_8UC1, bytes), out, code);
      return out;
    }
    case ARV_PIXEL_FORMAT_RGB_8_PACKED:
      if (!need(3)) return std::nullopt;
      cv::cvtColor(cv::Mat(h, w, CV_8UC3, bytes), out, cv::COLOR_RGB2GRAY);
      return out;
    case ARV_PIXEL_FORMAT_BGR_8_PACKED:
      if (!need(3)) return std::nullopt;
      cv::cvtColor(cv::Mat(h, w, CV_8UC3, bytes), out, cv::COLOR_BGR2GRAY);
      return out;
    default:
      return std::nullopt;
  }
}

void OnControlLost(ArvDevice*, gpointer data) {
  // Called from Aravis's heartbeat thread: only flag it.
  static_cast<std::atomic<bool>*>(data)->store(true);
}

}  // namespace

std::mutex& AravisSetupMutex() {
  static std::mutex m;
  return m;
}

std::vector<CameraInfo> ListCameras() {
  std::lock_guard<std::mutex> lock(AravisSetupMutex());
  arv_update_device_list();
  std::vector<CameraInfo> out;
  auto str = [](const char* s) { return std::string(s != nullptr ? s : ""); };
  for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
    out.push_back({str(arv_get_device_id(i)), str(arv_get_device_vendor(i)),
                   str(arv_get_device_model(i)), str(arv_get_device_serial_nbr(i)),
                   str(arv_get_device_address(i)), str(arv_get_device_protocol(i))});
  }
  return out;
}

Result<std::unique_ptr<AravisSource>> AravisSource::Open(const AravisOptions& options) {
  if (options.device.empty())
    return Fail(ErrorCode::kInvalidArgument, "no camera given (an id, IP address or serial)");
  std::unique_ptr<AravisSource> src(new AravisSource());
  src->id_ = options.device;
  GErrorSlot err;
  if (std::find(kBuiltInSimulatedCameras.begin(), kBuiltInSimulatedCameras.end(), options.device) !=
      kBuiltInSimulatedCameras.end()) {
    // Aravis's in-process fake device: the same ArvCamera API and stream, no network.
    SimCameraOptions sim;
    sim.scene = options.device == "sim-floor" ? SimScene::kFloor : SimScene::kCorner;
    sim.realistic = options.device == "sim-corner-realistic";
    // A fake camera's serial fits 15 characters (SimScenes checks): "sim-corner-realistic"
    // is 20.
    sim.serial = options.device.size() <= 15 ? options.device : "sim-realistic";
    sim.trajectory_frames = 8;
    sim.cancelled = options.cancelled;
    auto scenes = SimScenes::Render(sim);
    if (!scenes) return scenes.error();
    src->scenes_ = *scenes;
    std::lock_guard<std::mutex> lock(AravisSetupMutex());  // held until it streams
    src->fake_device_ = GObjectPtr<ArvDevice>(arv_fake_device_new(sim.serial.c_str(), err.out()));
    if (!src->fake_device_)
      return Fail(ErrorCode::kIo, "cannot create simulated camera: " + err.message());
    src->scenes_->Attach(arv_fake_device_get_fake_camera(ARV_FAKE_DEVICE(src->fake_device_.get())));
    // The camera takes its own reference to the device.
    src->camera_ =
        GObjectPtr<ArvCamera>(arv_camera_new_with_device(src->fake_device_.get(), err.out()));
    if (!src->camera_)
      return Fail(ErrorCode::kIo, "cannot open simulated camera: " + err.message());
    src->info_ = {options.device, "monocle",    "simulated (Aravis Fake)",
                  options.device, "in-process", "Fake"};
    return Start(std::move(src), options);
  }
  if (options.device.starts_with("sim-")) {
    // A misspelled simulator is a configuration error, not a camera still to be found.
    std::string known;
    for (const char* id : kBuiltInSimulatedCameras)
      known += (known.empty() ? "" : ", ") + std::string(id);
    return Fail(ErrorCode::kInvalidArgument,
                "'" + options.device + "' is not a built-in simulated camera (" + known + ")");
  }
  std::lock_guard<std::mutex> lock(AravisSetupMutex());  // held until it streams
  const auto device = ResolveDevice(options.device);
  if (!device) {
    return Fail(ErrorCode::kNotFound,
                "no camera '" + options.device +
                    "' (not an Aravis device id, IP address or serial number seen on this "
                    "machine; `monocle cameras` lists them)");
  }
  src->camera_ = GObjectPtr<ArvCamera>(arv_camera_new(device->c_str(), err.out()));
  if (!src->camera_) {
    return Fail(ErrorCode::kNotFound,
                "cannot open camera '" + options.device + "': " + err.message());
  }
  ArvCamera* cam = src->camera_.get();
  auto str = [](const char* s) { return std::string(s != nullptr ? s : ""); };
  src->info_ = {*device,
                str(arv_camera_get_vendor_name(cam, nullptr)),
                str(arv_camera_get_model_name(cam, nullptr)),
                str(arv_camera_get_device_serial_number(cam, nullptr)),
                "",
                arv_camera_is_gv_device(cam) ? "GigEVision"
                                             : (arv_camera_is_uv_device(cam) ? "USB3Vision" : "")};
  return Start(std::move(src), options);
}

Result<std::unique_ptr<AravisSource>> AravisSource::Start(std::unique_ptr<AravisSource> src,
                                                          const AravisOptions& options) {
  ArvCamera* cam = src->camera_.get();
  GErrorSlot err;
  if (auto s = Configure(cam, options); !s) return s.error();
  src->lost_handler_ = g_signal_connect(arv_camera_get_device(cam), "control-lost",
                                        G_CALLBACK(OnControlLost), &src->state_->lost);
  src->stream_ = std::make_shared<GObjectPtr<ArvStream>>(
      arv_camera_create_stream(cam, nullptr, nullptr, err.out()));
  if (!*src->stream_)
    return Fail(ErrorCode::kIo, "cannot open the camera's stream: " + err.message());
  const size_t payload = arv_camera_get_payload(cam, err.out());
  if (err.failed() || payload == 0)
    return Fail(ErrorCode::kIo, "cannot read the camera's payload size: " + err.message());
  src->payload_ = payload;
  // With PTP on (SFNC PtpEnable, or GigE Vision 1.x GevIEEE1588), the camera's timestamps
  // are a clock shared with the host's network: use them.
  for (const char* feature : {"PtpEnable", "GevIEEE1588"}) {
    GErrorSlot probe;
    if (arv_camera_is_feature_available(cam, feature, probe.out()) && !probe.failed()) {
      const gboolean on = arv_camera_get_boolean(cam, feature, probe.out());
      if (!probe.failed() && on) src->ptp_ = true;
    }
  }
  for (int i = 0; i < std::max(options.buffers, 2); ++i) {
    Requeue(src->stream_->get(), arv_buffer_new_allocate(payload));
  }
  arv_camera_start_acquisition(cam, err.out());
  if (err.failed()) return Fail(ErrorCode::kIo, "cannot start acquisition: " + err.message());
  return src;
}

AravisSource::~AravisSource() {
  if (camera_) {
    // A camera whose control channel is lost cannot be told to stop.
    if (!state_->lost.load()) arv_camera_stop_acquisition(camera_.get(), nullptr);
    if (lost_handler_ != 0)
      g_signal_handler_disconnect(arv_camera_get_device(camera_.get()), lost_handler_);
  }
}

Result<Frame> AravisSource::Next(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (state_->lost.load())
      return Fail(ErrorCode::kIo, "camera '" + id_ + "' was lost (control-lost)");
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      return Fail(ErrorCode::kNotFound, "no frame from camera '" + id_ + "' within " +
                                            std::to_string(timeout.count()) + " ms");
    }
    ArvBuffer* buffer =
        arv_stream_timeout_pop_buffer(stream_->get(), static_cast<guint64>(left.count()));
    if (buffer == nullptr) continue;
    BufferTakenOver(buffer);
    if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {
      ++dropped_;
      Requeue(stream_->get(), buffer);
      continue;
    }
    auto grey = GreyView(buffer, payload_);
    if (!grey) {
      Requeue(stream_->get(), buffer);
      return Fail(ErrorCode::kInvalidArgument,
                  "camera '" + id_ + "' sent a frame in a pixel format monocle cannot read");
    }
    Frame f;
    f.sequence = arv_buffer_get_frame_id(buffer);
    f.camera_id = id_;
    // The camera's own timestamp is a common clock only when PTP runs; otherwise report the
    // host's time of reception, which Aravis records.
    f.time_source = ptp_ ? TimeSource::kCamera : TimeSource::kHost;
    f.capture_time_ns = static_cast<int64_t>(ptp_ ? arv_buffer_get_timestamp(buffer)
                                                  : arv_buffer_get_system_timestamp(buffer));
    f.device_time_ns = static_cast<int64_t>(arv_buffer_get_timestamp(buffer));
    const bool view = grey->data == arv_buffer_get_image_data(buffer, nullptr);
    f.grey = *grey;
    if (view && kThreadSanitizer) {
      {
        IgnoredReadsOfForeignBuffer ignore;
        f.grey = grey->clone();
      }
      Requeue(stream_->get(), buffer);
    } else if (view) {
      // Zero copy: the frame returns the buffer to the stream when the last user lets go.
      auto stream = stream_;
      f.keepalive = std::shared_ptr<void>(
          buffer, [stream](void* b) { Requeue(stream->get(), static_cast<ArvBuffer*>(b)); });
    } else {
      Requeue(stream_->get(), buffer);
    }
    return f;
  }
}

}  // namespace monocle
