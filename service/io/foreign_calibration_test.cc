#include "service/io/foreign_calibration.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core/persistence.hpp>

namespace monocle {
namespace {

CameraIntrinsics Known() {
  CameraIntrinsics k;
  k.width_px = 1280;
  k.height_px = 1024;
  k.fx = 1624.25;
  k.fy = 1622.5;
  k.cx = 641.75;
  k.cy = 509.125;
  k.distortion = {-0.21, 0.13, 0.0012, -0.0007, -0.035, 0, 0, 0};
  return k;
}

void ExpectSame(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  EXPECT_EQ(a.width_px, b.width_px);
  EXPECT_EQ(a.height_px, b.height_px);
  EXPECT_DOUBLE_EQ(a.fx, b.fx);
  EXPECT_DOUBLE_EQ(a.fy, b.fy);
  EXPECT_DOUBLE_EQ(a.cx, b.cx);
  EXPECT_DOUBLE_EQ(a.cy, b.cy);
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(a.distortion[i], b.distortion[i]) << i;
}

// As camera_calibration_parsers writes it (ROS 2's camera_info_manager loads these).
constexpr const char* kRosYaml = R"(image_width: 1280
image_height: 1024
camera_name: ceiling_cam
camera_matrix:
  rows: 3
  cols: 3
  data: [1624.25, 0, 641.75, 0, 1622.5, 509.125, 0, 0, 1]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.21, 0.13, 0.0012, -0.0007, -0.035]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [1624.25, 0, 641.75, 0, 0, 1622.5, 509.125, 0, 0, 0, 1, 0]
)";

TEST(ForeignCalibrationTest, ReadsRosCameraInfo) {
  const auto got = ParseRosCameraInfo(kRosYaml, "cam.yaml");
  ASSERT_TRUE(got.ok()) << got.error();
  ExpectSame(got->intrinsics, Known());
  EXPECT_EQ(got->camera_name, "ceiling_cam");
  EXPECT_EQ(got->distortion_model, "k1k2p1p2k3");
}

TEST(ForeignCalibrationTest, RosExportReadsBackExactly) {
  CameraIntrinsics k = Known();
  k.fx = 1624.123456789012;  // all 17 digits must survive
  const auto back = ParseRosCameraInfo(FormatRosCameraInfo(k, "ceiling_cam"), "export");
  ASSERT_TRUE(back.ok()) << back.error();
  ExpectSame(back->intrinsics, k);
  k.distortion[5] = 0.01;  // a rational lens: eight terms, rational_polynomial
  const std::string rational = FormatRosCameraInfo(k, "");
  EXPECT_NE(rational.find("distortion_model: rational_polynomial"), std::string::npos);
  const auto back8 = ParseRosCameraInfo(rational, "export");
  ASSERT_TRUE(back8.ok()) << back8.error();
  ExpectSame(back8->intrinsics, k);
}

// OpenCV's FileStorage, YAML and XML, written here by OpenCV itself.
TEST(ForeignCalibrationTest, ReadsOpenCvFileStorageYamlAndXml) {
  const CameraIntrinsics k = Known();
  for (const char* name : {"cam.yml", "cam.xml"}) {
    cv::FileStorage fs(name, cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "image_width" << k.width_px << "image_height" << k.height_px;
    fs << "camera_matrix" << (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    fs << "distortion_coefficients"
       << (cv::Mat_<double>(5, 1) << k.distortion[0], k.distortion[1], k.distortion[2],
           k.distortion[3], k.distortion[4]);
    const std::string text = fs.releaseAndGetString();
    const auto got = ParseOpenCvCalibration(text, name, std::nullopt);
    ASSERT_TRUE(got.ok()) << got.error();
    ExpectSame(got->intrinsics, k);
    EXPECT_NE(got->format.find(std::string(name).ends_with("xml") ? "XML" : "YAML"),
              std::string::npos);
  }
}

// OpenCV's own calibration of its left photos (Debian's opencv-doc), as its sample wrote it.
TEST(ForeignCalibrationTest, ReadsOpenCvsOwnLeftIntrinsics) {
  const std::string path = "/usr/share/doc/opencv-doc/examples/data/left_intrinsics.yml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not installed (opencv-doc)";
  const auto got = LoadForeignCalibration(path, ForeignFormat::kAuto, std::nullopt);
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_EQ(got->intrinsics.width_px, 640);
  EXPECT_EQ(got->intrinsics.height_px, 480);
  EXPECT_DOUBLE_EQ(got->intrinsics.fx, 5.3591573396163199e+02);
  EXPECT_DOUBLE_EQ(got->intrinsics.cy, 2.3557082909788173e+02);
  EXPECT_DOUBLE_EQ(got->intrinsics.distortion[4], 2.3839153080878486e-01);
  EXPECT_EQ(got->distortion_model, "k1k2p1p2k3");
}

TEST(ForeignCalibrationTest, ErrorsNameTheFileTheLineAndTheField) {
  std::string text = kRosYaml;
  text.replace(text.find("[1624.25, 0, 641.75"), 7, "[fx");
  auto r = ParseRosCameraInfo(text, "cam.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cam.yaml:7: field 'camera_matrix.data' has a value that is "
                                   "not a number"),
            std::string::npos)
      << r.error();
  r = ParseRosCameraInfo("image_width: [1280\n", "bad.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad.yaml:"), std::string::npos) << r.error();
  text = kRosYaml;
  text.replace(text.find("plumb_bob"), 9, "equidistant");
  r = ParseRosCameraInfo(text, "fisheye.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("fisheye.yaml:8: field 'distortion_model' is 'equidistant'"),
            std::string::npos)
      << r.error();
  text = kRosYaml;
  text.replace(text.find("641.75, 0, 1622.5"), 6, "1641.7");
  r = ParseRosCameraInfo(text, "cam.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("outside the 1280x1024 image"), std::string::npos) << r.error();
  // OpenCV's file without the image size: say how to give it.
  cv::FileStorage fs("x.yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "camera_matrix" << cv::Mat(cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1));
  const std::string no_size = fs.releaseAndGetString();
  r = ParseOpenCvCalibration(no_size, "x.yml", std::nullopt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("--image-size"), std::string::npos) << r.error();
  const auto sized = ParseOpenCvCalibration(no_size, "x.yml", ImageSize{640, 480});
  ASSERT_TRUE(sized.ok()) << sized.error();
  EXPECT_EQ(sized->distortion_model, "");
}

}  // namespace
}  // namespace monocle
