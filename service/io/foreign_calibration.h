// Camera calibrations other tools wrote, read into monocle's intrinsics and written back:
// ROS's camera_info YAML (camera_calibration_parsers' format, what a ROS 2 camera driver
// loads) and OpenCV's FileStorage output (YAML or XML: camera_matrix, distortion_coefficients
// and the image size, as OpenCV's calibration sample writes them). Neither carries a
// covariance: measurements made with an imported calibration say that their 1 sigma leaves
// the calibration's uncertainty out.
#pragma once

#include <optional>
#include <string>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"

namespace monocle {

enum class ForeignFormat {
  kAuto,    // by the content: OpenCV FileStorage starts "%YAML:1.0" or "<?xml"
  kRos,     // camera_info YAML
  kOpenCv,  // FileStorage YAML or XML
};

Result<ForeignFormat> ParseForeignFormat(const std::string& text);  // "auto", "ros", "opencv"

struct ForeignCalibration {
  CameraIntrinsics intrinsics;
  std::string format;            // for people: "ROS camera_info YAML", "OpenCV FileStorage XML"
  std::string camera_name;       // ROS camera_name; empty when the file has none
  std::string distortion_model;  // monocle's name for the terms given; empty for none/rational
};

// An image size for files that do not carry one (OpenCV's without image_width/height).
struct ImageSize {
  int width_px = 0;
  int height_px = 0;
};

// Errors name the file, the line where the format gives one, and the field.
Result<ForeignCalibration> ParseRosCameraInfo(const std::string& text, const std::string& source);
Result<ForeignCalibration> ParseOpenCvCalibration(const std::string& text,
                                                  const std::string& source,
                                                  std::optional<ImageSize> image_size);
Result<ForeignCalibration> LoadForeignCalibration(const std::string& path, ForeignFormat format,
                                                  std::optional<ImageSize> image_size);

// camera_info YAML as camera_calibration_parsers writes it: plumb_bob (5 terms) or
// rational_polynomial (8), identity rectification, projection [K | 0].
std::string FormatRosCameraInfo(const CameraIntrinsics& k, const std::string& camera_name);

}  // namespace monocle
