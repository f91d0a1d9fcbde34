// `monocle intrinsics import` and `export`, as a robot's user runs them: a calibration another
// tool wrote (ROS camera_info YAML, OpenCV FileStorage YAML and XML, each written here from
// known values, and OpenCV's own left_intrinsics.yml) becomes a monocle calibration file that
// measures exactly what the native file does, and says its 1 sigma leaves the calibration out.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core/persistence.hpp>

#include "idl/cli_output.pb.h"
#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

class CalibrationImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    CameraCalibration truth;
    truth.intrinsics = testing::PaperCamera();
    truth.floor = FloorCalibration{};
    truth.floor->pose = FloorPose{1.05, testing::Deg(118), testing::Deg(4), testing::Deg(1.5)};
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "truth.pbtxt", truth).ok());
    CameraCalibration native;
    native.intrinsics = truth.intrinsics;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "native.pbtxt", native).ok());
    const auto r =
        RunMonocle(dir_, "render floor --calibration " + dir_ / "truth.pbtxt" +
                             " --board 11x8 --square 0.05 --noise 2 --out " + dir_ / "board.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }

  // `floor calibrate --json` of the board with `calibration`.
  proto::FloorCalibrationOutput FloorWith(const std::string& calibration, std::string* err) {
    const auto r = RunMonocle(dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " +
                                        calibration + " --board 11x8 --square 0.05 --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    *err = r.err;
    proto::FloorCalibrationOutput out;
    EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
    return out;
  }

  TempDir dir_{"monocle_calibration_import"};
};

void WriteOpenCv(const std::string& path, const CameraIntrinsics& k) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  fs << "image_width" << k.width_px << "image_height" << k.height_px;
  fs << "camera_matrix" << (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  fs << "distortion_coefficients"
     << (cv::Mat_<double>(1, 5) << k.distortion[0], k.distortion[1], k.distortion[2],
         k.distortion[3], k.distortion[4]);
}

void WriteRos(const std::string& path, const CameraIntrinsics& k) {
  std::ofstream out(path);
  out.precision(17);
  out << "image_width: " << k.width_px << "\nimage_height: " << k.height_px
      << "\ncamera_name: floor_cam\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [" << k.fx
      << ", 0, " << k.cx << ", 0, " << k.fy << ", " << k.cy
      << ", 0, 0, 1]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n"
      << "  cols: 5\n  data: [" << k.distortion[0] << ", " << k.distortion[1] << ", "
      << k.distortion[2] << ", " << k.distortion[3] << ", " << k.distortion[4]
      << "]\nrectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n";
}

TEST_F(CalibrationImportTest, EachFormatMeasuresWhatTheNativeFileDoes) {
  const CameraIntrinsics k = testing::PaperCamera();
  WriteRos(dir_ / "ros.yaml", k);
  WriteOpenCv(dir_ / "opencv.yml", k);
  WriteOpenCv(dir_ / "opencv.xml", k);
  std::string native_err;
  const auto native = FloorWith(dir_ / "native.pbtxt", &native_err);
  EXPECT_TRUE(native.sigma_excludes_intrinsics());
  EXPECT_NE(native_err.find("leaves the calibration's uncertainty out"), std::string::npos)
      << native_err;
  for (const std::string name : {"ros.yaml", "opencv.yml", "opencv.xml"}) {
    const std::string out = dir_ / (name + ".pbtxt");
    const auto r = RunMonocle(dir_, "intrinsics import " + dir_ / name + " --out " + out);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_NE(r.err.find("has no covariance"), std::string::npos) << r.err;
    std::string err;
    const auto imported = FloorWith(out, &err);
    EXPECT_EQ(imported.height(), native.height()) << name;
    EXPECT_EQ(imported.pitch(), native.pitch()) << name;
    EXPECT_EQ(imported.yaw(), native.yaw()) << name;
    EXPECT_EQ(imported.sigma().height(), native.sigma().height()) << name;
    EXPECT_TRUE(imported.sigma_excludes_intrinsics()) << name;
  }
  // A file calibrated by monocle carries its covariance: no such warning, and the flag off.
  CameraCalibration with_covariance = *LoadCalibrationFile(dir_ / "native.pbtxt");
  with_covariance.intrinsics_covariance = IntrinsicsCovariance::Identity() * 1e-6;
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "cov.pbtxt", with_covariance).ok());
  std::string err;
  EXPECT_FALSE(FloorWith(dir_ / "cov.pbtxt", &err).sigma_excludes_intrinsics());
  EXPECT_EQ(err.find("no covariance"), std::string::npos) << err;
}

// OpenCV's own output for its left photos (Debian's opencv-doc): the file imported holds its
// numbers exactly, as a native file typed from them would.
TEST_F(CalibrationImportTest, ReadsOpenCvsOwnLeftIntrinsics) {
  const std::string path = "/usr/share/doc/opencv-doc/examples/data/left_intrinsics.yml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not installed (opencv-doc)";
  const auto r = RunMonocle(dir_, "intrinsics import " + path + " --out " + dir_ / "left.pbtxt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto got = LoadCalibrationFile(dir_ / "left.pbtxt");
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_EQ(got->intrinsics.width_px, 640);
  EXPECT_DOUBLE_EQ(got->intrinsics.fx, 5.3591573396163199e+02);
  EXPECT_DOUBLE_EQ(got->intrinsics.cx, 3.4228315473308373e+02);
  EXPECT_DOUBLE_EQ(got->intrinsics.distortion[0], -2.6637260909660682e-01);
  EXPECT_DOUBLE_EQ(got->intrinsics.distortion[4], 2.3839153080878486e-01);
  EXPECT_EQ(got->distortion_model, "k1k2p1p2k3");
}

// Export for a ROS 2 camera driver, and back: the same intrinsics; a floor section in the
// file imported into is removed (it was made with other intrinsics), its corner section kept.
TEST_F(CalibrationImportTest, ExportedRosYamlImportsBackAndOldFloorGoes) {
  auto r = RunMonocle(dir_, "intrinsics export " + dir_ / "truth.pbtxt" +
                                " --ros --camera-name floor_cam --out " + dir_ / "exported.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  CameraCalibration existing = *LoadCalibrationFile(dir_ / "truth.pbtxt");
  existing.ceiling_distance_m = 1.5;
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "robot.pbtxt", existing).ok());
  r = RunMonocle(dir_,
                 "intrinsics import " + dir_ / "exported.yaml" + " --out " + dir_ / "robot.pbtxt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("floor section"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("camera floor_cam"), std::string::npos) << r.out;
  const auto back = LoadCalibrationFile(dir_ / "robot.pbtxt");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_FALSE(back->floor.has_value());
  EXPECT_EQ(back->ceiling_distance_m, 1.5);
  const CameraIntrinsics k = testing::PaperCamera();
  EXPECT_DOUBLE_EQ(back->intrinsics.fx, k.fx);
  EXPECT_DOUBLE_EQ(back->intrinsics.cy, k.cy);
  EXPECT_DOUBLE_EQ(back->intrinsics.distortion[3], k.distortion[3]);
  // A broken file: refused with the file, line and field, nothing written.
  std::ofstream(dir_ / "broken.yaml") << "image_width: 1280\nimage_height: 1024\n"
                                      << "camera_matrix:\n  rows: 3\n  data: [1, 2]\n";
  const std::string before = testing::ReadFile(dir_ / "robot.pbtxt");
  r = RunMonocle(dir_,
                 "intrinsics import " + dir_ / "broken.yaml" + " --out " + dir_ / "robot.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("broken.yaml:4: field 'camera_matrix.data' must be a 3x3 matrix"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(testing::ReadFile(dir_ / "robot.pbtxt"), before);
}

}  // namespace
}  // namespace monocle
