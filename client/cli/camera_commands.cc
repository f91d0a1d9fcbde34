// monocle cameras | snapshot: cameras through Aravis.
#include <cmath>
#include <csignal>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "camera/aravis/aravis_source.h"
#include "client/cli/args.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"

namespace monocle::cli {
namespace {

int Cameras(const std::vector<std::string>& argv) {
  bool json = false;
  CommandLine line("cameras",
                   "Lists the cameras Aravis sees (GigE Vision and USB3 Vision): id, vendor, "
                   "model, serial,\naddress, interface. A simulated camera on 127.0.0.1 may not "
                   "be discovered: open it by its\naddress (monocle snapshot 127.0.0.1 ...).");
  line.Flag("--json", &json, "print one JSON array");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto cams = ListCameras();
  if (json) {
    std::cout << "[";
    for (size_t i = 0; i < cams.size(); ++i) {
      const auto& c = cams[i];
      std::cout << (i ? "," : "") << "{\"id\":\"" << c.id << "\",\"vendor\":\"" << c.vendor
                << "\",\"model\":\"" << c.model << "\",\"serial\":\"" << c.serial
                << "\",\"address\":\"" << c.address << "\",\"interface\":\"" << c.protocol << "\"}";
    }
    std::cout << "]\n";
    return kExitOk;
  }
  if (cams.empty()) std::cout << "no cameras found\n";
  for (const auto& c : cams) {
    std::cout << c.id << "  " << c.vendor << " " << c.model << "  serial " << c.serial << "  "
              << c.address << "  " << c.protocol << "\n";
  }
  std::cout << "built-in simulated cameras, no hardware needed:";
  for (const char* id : kBuiltInSimulatedCameras) std::cout << " " << id;
  std::cout << "\n(monocle snapshot sim-corner --out frame.png; device: \"sim-corner\" in "
               "monocled's configuration)\n";
  return kExitOk;
}

struct SnapshotArgs {
  std::vector<std::string> camera;
  std::string out;
  double timeout_ms = 3000;
  AravisOptions options;
};

// "X,Y,W,H" in pixels.
Result<std::array<int, 4>> ParseRegion(const std::string& text) {
  const auto v = ParseNumberList(text);
  if (!v || v->size() != 4)
    return MakeError(ErrorCode::kInvalidArgument, "'" + text + "' is not X,Y,W,H in pixels");
  return std::array<int, 4>{static_cast<int>((*v)[0]), static_cast<int>((*v)[1]),
                            static_cast<int>((*v)[2]), static_cast<int>((*v)[3])};
}

void DeclareSnapshot(CommandLine& line, SnapshotArgs* a) {
  line.Footer(
      "Every value is checked against the camera's range first; the error names the feature.\n"
      "The ids sim-corner, sim-corner-realistic (a white-painted room) and sim-floor are "
      "built-in\nsimulated cameras.");
  AravisOptions& o = a->options;
  o.pixel_format = "Mono8";
  line.Positionals("CAMERA", &a->camera, "an Aravis device id, an IPv4 address or a serial number",
                   1, 1);
  line.Text("--out", &a->out, "IMG.png", "the frame, as 8-bit grey");
  line.Require("--out");
  line.Text("--pixel-format", &o.pixel_format, "F",
            "GenICam pixel format to request (default "
            "Mono8)");
  line.Number("--timeout", &a->timeout_ms, "MS", "how long to wait for a frame",
              In("milliseconds").Above(0));
  line.Number("--exposure", &o.exposure_us, "US", "exposure time", In("microseconds"));
  line.Number("--gain", &o.gain, "DB", "gain", In("dB"));
  line.Number("--fps", &o.frame_rate_hz, "HZ", "frame rate", In("Hz"));
  line.Parsed<std::array<int, 4>>("--region", &o.region, "X,Y,W,H", "region of interest, pixels",
                                  ParseRegion);
  line.Whole("--packet-size", &o.packet_size_bytes, "B", "GigE Vision packet size",
             In("bytes").AtLeast(0));
  line.Whole("--packet-delay", &o.inter_packet_delay_ticks, "T", "GigE Vision inter-packet delay",
             In("ticks").AtLeast(0));
  line.CustomRepeated("--feature", "NAME=VALUE", "any other GenICam feature by name",
                      [&o](const std::string& f) -> std::optional<std::string> {
                        const auto eq = f.find('=');
                        if (eq == std::string::npos || eq == 0)
                          return "'" + f + "' is not NAME=VALUE";
                        o.features.emplace_back(f.substr(0, eq), f.substr(eq + 1));
                        return std::nullopt;
                      });
}

int Snapshot(const std::vector<std::string>& argv) {
  SnapshotArgs a;
  CommandLine line("snapshot",
                   "Grabs one frame from CAMERA (an Aravis device id, an IPv4 address or a serial "
                   "number)\nand writes it as 8-bit grey (Mono16, Bayer and RGB frames are "
                   "converted).");
  DeclareSnapshot(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  AravisOptions& options = a.options;
  options.device = a.camera[0];
  const std::string* out = &a.out;
  const double* timeout = &a.timeout_ms;
  auto source = AravisSource::Open(options);
  if (!source) return Fail(source.error(), kExitFailure);
  const auto frame = (*source)->Next(std::chrono::milliseconds(static_cast<int64_t>(*timeout)));
  if (!frame) return Fail(frame.error(), kExitFailure);
  if (auto written = WriteImage(*out, frame->grey); !written)
    return Fail(written.error(), kExitFailure);
  std::cout << "frame " << frame->sequence << " " << frame->grey.cols << "x" << frame->grey.rows
            << " from " << (*source)->info().vendor << " " << (*source)->info().model
            << " written to " << *out << "\n";
  return kExitOk;
}

}  // namespace

int CameraCommand(const std::string& command, const std::vector<std::string>& args) {
  if (command == "cameras") return Cameras(args);
  if (command == "snapshot") return Snapshot(args);
  return SimcamCommand(args);
}

}  // namespace monocle::cli
