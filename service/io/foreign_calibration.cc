#include "service/io/foreign_calibration.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <iomanip>
#include <opencv2/core.hpp>
#include <sstream>
#include <vector>

#include "service/io/bounded_file.h"

namespace monocle {
namespace {

Error Invalid(const std::string& where, const std::string& field, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, where + ": field '" + field + "' " + why);
}

std::string At(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? source : source + ":" + std::to_string(mark.line + 1);
}

// The distortion terms in OpenCV's order into `out` (0, 4, 5 or 8; the thin-prism and tilt
// terms of 12 and 14 only when they are zero), and monocle's model name for them.
Status SetDistortion(const std::vector<double>& terms, const std::string& where,
                     const std::string& field, ForeignCalibration* out) {
  size_t used = terms.size();
  if (used == 12 || used == 14) {
    for (size_t i = 8; i < used; ++i)
      if (terms[i] != 0)
        return Invalid(where, field,
                       "has thin-prism or tilt terms (s1..s4, tx, ty), which "
                       "monocle's lens model does not have");
    used = 8;
  }
  if (used != 0 && used != 4 && used != 5 && used != 8) {
    return Invalid(where, field,
                   "must have 0, 4 (k1 k2 p1 p2), 5 (+k3) or 8 (+k3..k6) values, not " +
                       std::to_string(terms.size()));
  }
  for (size_t i = 0; i < used; ++i) {
    if (!std::isfinite(terms[i]) || std::abs(terms[i]) > 1e4)
      return Invalid(where, field, "value " + std::to_string(i + 1) + " is not a finite term");
    out->intrinsics.distortion[i] = terms[i];
  }
  out->distortion_model = used == 4 ? "k1k2p1p2" : used == 5 ? "k1k2p1p2k3" : "";
  return Ok{};
}

// The camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (row-major) into `out`, checked against the
// image size already set.
Status SetCameraMatrix(const std::vector<double>& m, const std::string& where,
                       const std::string& field, ForeignCalibration* out) {
  if (m.size() != 9) {
    return Invalid(where, field,
                   "must be a 3x3 matrix (9 values), not " + std::to_string(m.size()) + " values");
  }
  auto& k = out->intrinsics;
  if (!(m[0] > 0) || !(m[4] > 0) || !std::isfinite(m[0]) || !std::isfinite(m[4]))
    return Invalid(where, field, "must have positive focal lengths fx (value 1) and fy (value 5)");
  if (m[1] != 0 || m[3] != 0 || m[6] != 0 || m[7] != 0 || m[8] != 1)
    return Invalid(where, field, "must be [fx 0 cx; 0 fy cy; 0 0 1] (no skew)");
  if (!(m[2] >= 0 && m[2] <= k.width_px) || !(m[5] >= 0 && m[5] <= k.height_px)) {
    return Invalid(where, field,
                   "puts the principal point (values 3 and 6) outside the " +
                       std::to_string(k.width_px) + "x" + std::to_string(k.height_px) + " image");
  }
  k.fx = m[0];
  k.cx = m[2];
  k.fy = m[4];
  k.cy = m[5];
  return Ok{};
}

Result<std::vector<double>> RosMatrixData(const YAML::Node& root, const std::string& name,
                                          const std::string& source) {
  const YAML::Node node = root[name];
  if (!node) return Invalid(source, name, "is missing");
  const YAML::Node data = node["data"];
  if (!data || !data.IsSequence()) return Invalid(At(source, node), name + ".data", "is missing");
  std::vector<double> values;
  for (const auto& v : data) {
    try {
      values.push_back(v.as<double>());
    } catch (const YAML::Exception&) {
      return Invalid(At(source, v), name + ".data", "has a value that is not a number");
    }
  }
  return values;
}

Status SetImageSize(int width, int height, const std::string& where, ForeignCalibration* out) {
  if (width <= 0 || width > 65535 || height <= 0 || height > 65535) {
    return Invalid(where, "image_width/image_height",
                   "must be the image size in pixels (1..65535), not " + std::to_string(width) +
                       "x" + std::to_string(height));
  }
  out->intrinsics.width_px = width;
  out->intrinsics.height_px = height;
  return Ok{};
}

Result<ForeignCalibration> ParseRosTree(const YAML::Node& root, const std::string& source) {
  ForeignCalibration out;
  out.format = "ROS camera_info YAML";
  if (!root.IsMap()) return Invalid(source, "(top level)", "must be a map of camera_info fields");
  int size[2] = {0, 0};
  const char* size_fields[2] = {"image_width", "image_height"};
  for (int i = 0; i < 2; ++i) {
    const YAML::Node n = root[size_fields[i]];
    if (!n) return Invalid(source, size_fields[i], "is missing");
    try {
      size[i] = n.as<int>();
    } catch (const YAML::Exception&) {
      return Invalid(At(source, n), size_fields[i], "must be a whole number of pixels");
    }
  }
  if (auto s = SetImageSize(size[0], size[1], source, &out); !s) return s.error();
  if (const YAML::Node name = root["camera_name"]; name && name.IsScalar())
    out.camera_name = name.as<std::string>();
  const YAML::Node model = root["distortion_model"];
  const std::string model_name = model ? model.as<std::string>("") : "plumb_bob";
  if (model_name != "plumb_bob" && model_name != "rational_polynomial") {
    return Invalid(At(source, model), "distortion_model",
                   "is '" + model_name +
                       "': monocle reads plumb_bob and rational_polynomial "
                       "(OpenCV's pinhole model), not fisheye/equidistant lenses");
  }
  auto matrix = RosMatrixData(root, "camera_matrix", source);
  if (!matrix) return matrix.error();
  if (auto s =
          SetCameraMatrix(*matrix, At(source, root["camera_matrix"]), "camera_matrix.data", &out);
      !s)
    return s.error();
  auto terms = RosMatrixData(root, "distortion_coefficients", source);
  if (!terms) return terms.error();
  if (auto s = SetDistortion(*terms, At(source, root["distortion_coefficients"]),
                             "distortion_coefficients.data", &out);
      !s)
    return s.error();
  return out;
}

// A FileStorage matrix node as row-major values, or empty when the node is absent.
std::vector<double> OpenCvMatrix(const cv::FileNode& node) {
  if (node.empty()) return {};
  cv::Mat m;
  node >> m;
  m.convertTo(m, CV_64F);
  return std::vector<double>(m.begin<double>(), m.end<double>());
}

// The first of `names` present in `fs` (OpenCV's samples and tools spell them differently).
cv::FileNode FirstOf(const cv::FileStorage& fs, std::initializer_list<const char*> names,
                     std::string* found) {
  for (const char* name : names) {
    cv::FileNode node = fs[name];
    if (!node.empty()) {
      *found = name;
      return node;
    }
  }
  return {};
}

}  // namespace

Result<ForeignFormat> ParseForeignFormat(const std::string& text) {
  if (text == "auto") return ForeignFormat::kAuto;
  if (text == "ros") return ForeignFormat::kRos;
  if (text == "opencv") return ForeignFormat::kOpenCv;
  return MakeError(ErrorCode::kInvalidArgument,
                   "--format '" + text + "' is not one of auto, ros, opencv");
}

Result<ForeignCalibration> ParseRosCameraInfo(const std::string& text, const std::string& source) {
  try {
    return ParseRosTree(YAML::Load(text), source);
  } catch (const YAML::Exception& e) {
    return MakeError(ErrorCode::kInvalidArgument,
                     source + ":" + std::to_string(e.mark.line + 1) + ": not YAML: " + e.msg);
  }
}

Result<ForeignCalibration> ParseOpenCvCalibration(const std::string& text,
                                                  const std::string& source,
                                                  std::optional<ImageSize> image_size) {
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    return MakeError(ErrorCode::kInvalidArgument,
                     source + ": not an OpenCV FileStorage file (" + e.err + ")");
  }
  if (!fs.isOpened())
    return MakeError(ErrorCode::kInvalidArgument, source + ": not an OpenCV FileStorage file");
  ForeignCalibration out;
  out.format = text.rfind("<?xml", 0) == 0 ? "OpenCV FileStorage XML" : "OpenCV FileStorage YAML";
  try {
    int width = image_size ? image_size->width_px : static_cast<int>(fs["image_width"].real());
    int height = image_size ? image_size->height_px : static_cast<int>(fs["image_height"].real());
    if (!image_size && fs["image_width"].empty()) {
      return Invalid(source, "image_width",
                     "is missing: give the image size with --image-size WIDTHxHEIGHT");
    }
    if (auto s = SetImageSize(width, height, source, &out); !s) return s.error();
    std::string name;
    const auto matrix = FirstOf(fs, {"camera_matrix", "cameraMatrix", "K"}, &name);
    if (matrix.empty())
      return Invalid(source, "camera_matrix", "is missing (also looked for cameraMatrix, K)");
    if (auto s = SetCameraMatrix(OpenCvMatrix(matrix), source, name, &out); !s) return s.error();
    const auto terms =
        FirstOf(fs, {"distortion_coefficients", "distCoeffs", "dist_coeffs", "D"}, &name);
    if (auto s = SetDistortion(OpenCvMatrix(terms), source,
                               terms.empty() ? "distortion_coefficients" : name, &out);
        !s)
      return s.error();
  } catch (const cv::Exception& e) {
    return MakeError(ErrorCode::kInvalidArgument, source + ": " + e.err);
  }
  return out;
}

Result<ForeignCalibration> LoadForeignCalibration(const std::string& path, ForeignFormat format,
                                                  std::optional<ImageSize> image_size) {
  auto text = ReadBoundedFile(path, "calibration file", kMaxTextFileBytes);
  if (!text) return text.error();
  if (format == ForeignFormat::kAuto) {
    const bool opencv = text->rfind("%YAML:", 0) == 0 || text->rfind("<?xml", 0) == 0;
    format = opencv ? ForeignFormat::kOpenCv : ForeignFormat::kRos;
  }
  if (format == ForeignFormat::kRos) return ParseRosCameraInfo(*text, path);
  return ParseOpenCvCalibration(*text, path, image_size);
}

std::string FormatRosCameraInfo(const CameraIntrinsics& k, const std::string& camera_name) {
  const bool rational = k.distortion[5] != 0 || k.distortion[6] != 0 || k.distortion[7] != 0;
  const int terms = rational ? 8 : 5;
  std::ostringstream os;
  os << std::setprecision(17);
  os << "image_width: " << k.width_px << "\nimage_height: " << k.height_px
     << "\ncamera_name: " << (camera_name.empty() ? "camera" : camera_name)
     << "\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [" << k.fx << ", 0, " << k.cx << ", 0, "
     << k.fy << ", " << k.cy
     << ", 0, 0, 1]\ndistortion_model: " << (rational ? "rational_polynomial" : "plumb_bob")
     << "\ndistortion_coefficients:\n  rows: 1\n  cols: " << terms << "\n  data: [";
  for (int i = 0; i < terms; ++i) os << (i ? ", " : "") << k.distortion[i];
  os << "]\nrectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]"
     << "\nprojection_matrix:\n  rows: 3\n  cols: 4\n  data: [" << k.fx << ", 0, " << k.cx
     << ", 0, 0, " << k.fy << ", " << k.cy << ", 0, 0, 0, 1, 0]\n";
  return os.str();
}

}  // namespace monocle
