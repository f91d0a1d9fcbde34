// monocle intrinsics import / export: calibrations made by other tools (a ROS camera_info
// YAML, OpenCV's FileStorage YAML or XML) into a monocle calibration file, and a monocle
// calibration out as the ROS YAML a ROS 2 camera driver loads.
#include <iostream>
#include <regex>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "service/io/calibration_file.h"
#include "service/io/foreign_calibration.h"

namespace monocle::cli {
namespace {

constexpr const char* kImportAbout =
    R"(Reads a camera calibration another tool wrote into CAL.pbtxt: a ROS camera_info YAML
(camera_calibration_parsers' format, what ROS camera drivers load) or OpenCV's FileStorage
YAML/XML (camera_matrix, distortion_coefficients, image_width, image_height, as OpenCV's
calibration sample writes them). Only OpenCV's pinhole model with 4, 5 or 8 distortion terms
is read (ROS plumb_bob and rational_polynomial). An existing CAL.pbtxt keeps its corner
section; its floor section, made with other intrinsics, is removed.

These files carry no covariance: the calibration is then taken as exact, and every 1 sigma
measured with it says that it leaves the calibration's uncertainty out. Calibrate with
`monocle intrinsics calibrate` to have it counted.)";

constexpr const char* kExportAbout =
    R"(Writes the intrinsics of a monocle calibration file as a ROS camera_info YAML
(camera_calibration_parsers' format: plumb_bob, or rational_polynomial for 8 terms; identity
rectification, projection [K | 0]), for a ROS 2 camera driver's camera_info_url.)";

struct ImportArgs {
  std::vector<std::string> file;
  std::string out_path;
  ForeignFormat format = ForeignFormat::kAuto;
  std::optional<ImageSize> image_size;
};

Result<ImageSize> ParseImageSize(const std::string& text) {
  static const std::regex size(R"((\d{1,5})x(\d{1,5}))");
  std::smatch m;
  if (!std::regex_match(text, m, size))
    return MakeError(ErrorCode::kInvalidArgument, "must be WIDTHxHEIGHT in pixels, e.g. 1280x1024");
  return ImageSize{std::stoi(m[1]), std::stoi(m[2])};
}

int Import(const std::vector<std::string>& argv) {
  ImportArgs a;
  CommandLine line("intrinsics import", kImportAbout);
  line.Positionals("FILE", &a.file, "the calibration to read (.yaml, .yml or .xml)", 1, 1);
  line.Text("--out", &a.out_path, "CAL.pbtxt", "calibration file to write atomically");
  line.Require("--out");
  line.Custom("--format", "auto|ros|opencv",
              "the file's format; auto (default): OpenCV's when it starts \"%YAML:1.0\" or "
              "\"<?xml\", ROS camera_info otherwise",
              [&a](const std::string& text) -> std::optional<std::string> {
                auto f = ParseForeignFormat(text);
                if (!f) return f.error().message;
                a.format = *f;
                return std::nullopt;
              });
  line.Parsed<ImageSize>("--image-size", &a.image_size, "WIDTHxHEIGHT",
                         "the image size in pixels, for an OpenCV file that does not say it",
                         ParseImageSize);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto foreign = LoadForeignCalibration(a.file[0], a.format, a.image_size);
  if (!foreign) return Fail(foreign.error(), kExitFailure);
  CameraCalibration file;
  bool floor_removed = false;
  if (auto existing = LoadCalibrationFile(a.out_path); existing) {
    file = *existing;
    floor_removed = file.floor.has_value();
    file.floor.reset();
  }
  file.intrinsics = foreign->intrinsics;
  file.intrinsics_rms_px = 0;
  file.intrinsics_covariance = IntrinsicsCovariance::Zero();
  file.distortion_model = foreign->distortion_model;
  // The same checks as any calibration file read, before anything is written.
  if (auto checked = ParseCalibration(FormatCalibration(file), a.file[0]); !checked)
    return Fail(checked.error(), kExitFailure);
  if (Status saved = SaveCalibrationFileAtomically(a.out_path, file); !saved)
    return Fail(saved.error(), kExitFailure);
  const auto& k = file.intrinsics;
  std::cout << "read        " << a.file[0] << " (" << foreign->format
            << (foreign->camera_name.empty() ? "" : ", camera " + foreign->camera_name) << ")\n"
            << "image       " << k.width_px << "x" << k.height_px << " px\n"
            << "fx fy cx cy " << k.fx << " " << k.fy << " " << k.cx << " " << k.cy << " px\n"
            << "written to  " << a.out_path << "\n";
  std::cerr << "monocle: warning: " << a.file[0]
            << " has no covariance: measurements with this calibration leave its uncertainty "
               "out of their 1 sigma (monocle intrinsics calibrate counts it)\n";
  if (floor_removed) {
    std::cerr << "monocle: warning: the floor section of " << a.out_path
              << " was made with the old intrinsics and is removed: run monocle floor "
                 "calibrate again\n";
  }
  return kExitOk;
}

int Export(const std::vector<std::string>& argv) {
  std::vector<std::string> calibration;
  bool ros = false;
  std::optional<std::string> out_path;
  std::string camera_name = "camera";
  CommandLine line("intrinsics export", kExportAbout);
  line.Positionals("CAL.pbtxt", &calibration, "the monocle calibration file", 1, 1);
  line.Flag("--ros", &ros, "write ROS camera_info YAML (the one format written today)");
  line.Require("--ros");
  line.Text("--out", &out_path, "FILE.yaml", "write there (atomically) instead of to stdout");
  line.Text("--camera-name", &camera_name, "NAME", "camera_name in the YAML");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto cal = LoadCalibrationFile(calibration[0]);
  if (!cal) return Fail(cal.error(), kExitFailure);
  const std::string yaml = FormatRosCameraInfo(cal->intrinsics, camera_name);
  if (!out_path) {
    std::cout << yaml;
    return kExitOk;
  }
  if (Status w = WriteFileAtomically(*out_path, yaml); !w) return Fail(w.error(), kExitFailure);
  return kExitOk;
}

}  // namespace

int IntrinsicsImportCommand(const std::vector<std::string>& args) { return Import(args); }
int IntrinsicsExportCommand(const std::vector<std::string>& args) { return Export(args); }

}  // namespace monocle::cli
