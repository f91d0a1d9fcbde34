// `monocle render corner` and `monocle corner locate` as a user runs them.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "camera/render/driving_path.h"
#include "idl/cli_output.pb.h"
#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"
#include "tests/integration/cli_process.h"
#include "tests/integration/mount_geometry.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) out.push_back(line);
  return out;
}

class CornerCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    CameraCalibration cal;
    cal.intrinsics = testing::PaperCamera();
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "nodistance.pbtxt", cal).ok());
    cal.ceiling_distance_m = 1.6;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "cal.pbtxt", cal).ok());
    cal.corner_max_swing_rad = 1.2;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "rolled.pbtxt", cal).ok());
  }
  TempDir dir_{"monocle_corner_cli"};
};

TEST_F(CornerCliTest, LocatesEachImageAndReportsFailuresPerImage) {
  // A corner in view (with clutter), then a view with no corner.
  auto r = RunMonocle(dir_,
                      "render corner --calibration " + dir_ / "cal.pbtxt" +
                          " --pose 2,1.5,1.6,2.2143,0.9,0.1 --noise 2 --clutter --lighting --out " +
                          dir_ / "a.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 3,1,1.6,1.9,0.7,-0.2 --out " + dir_ / "b.pgm");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  { std::ofstream(dir_ / "garbage.png") << "not an image"; }

  r = RunMonocle(dir_, "corner locate " + dir_ / "a.png" + " " + dir_ / "b.pgm" + " " +
                           dir_ / "garbage.png" + " " + dir_ / "missing.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --json --overlay " + dir_ / "overlays");
  EXPECT_EQ(r.exit_code, 1) << "some images failed";
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 4u) << r.out;
  std::vector<proto::CornerOutput> out(4);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(lines[i], &out[i]).ok()) << lines[i];
  }
  EXPECT_EQ(out[0].image(), dir_ / "a.png");
  ASSERT_FALSE(out[0].has_error()) << out[0].error();
  EXPECT_NEAR(out[0].x(), 2.0, 0.01);
  EXPECT_NEAR(out[0].y(), 1.5, 0.01);
  EXPECT_DOUBLE_EQ(out[0].z(), 1.6);
  EXPECT_NEAR(out[0].pan(), 2.2143, 0.005);
  EXPECT_NEAR(out[0].tilt(), 0.9, 0.005);
  EXPECT_NEAR(out[0].swing(), 0.1, 0.005);
  EXPECT_EQ(out[0].quaternion_size(), 4);
  EXPECT_EQ(out[0].corner_px_size(), 2);
  EXPECT_EQ(out[0].lines_size(), 3);
  EXPECT_GT(out[0].sigma().x(), 0);
  EXPECT_NE(out[1].error().find("no ceiling corner"), std::string::npos) << out[1].DebugString();
  EXPECT_NE(out[2].error().find("not an image format"), std::string::npos) << out[2].DebugString();
  EXPECT_NE(out[3].error().find("no such file"), std::string::npos) << out[3].DebugString();
  EXPECT_TRUE(std::filesystem::exists(dir_ / "overlays/a.overlay.png"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "overlays/b.overlay.png"));
}

TEST_F(CornerCliTest, CeilingDistanceFromTheCommandLineOrAClearError) {
  auto r =
      RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 2,1.5,2.0,2.2143,0.9,0.1 --noise 2 --out " + dir_ / "a.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_,
                 "corner locate " + dir_ / "a.png" + " --calibration " + dir_ / "nodistance.pbtxt");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--ceiling-distance"), std::string::npos) << r.err;
  r = RunMonocle(dir_, "corner locate " + dir_ / "a.png" + " --calibration " +
                           dir_ / "nodistance.pbtxt" + " --ceiling-distance 2.0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::CornerOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_NEAR(out.x(), 2.0, 0.01);
  EXPECT_DOUBLE_EQ(out.z(), 2.0);
  r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 2,1.5 --out " + dir_ / "x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("X,Y,Z,PAN,TILT,SWING"), std::string::npos) << r.err;
}

// Issue 62: at 1 m/s and 45 deg/s a realistic frame's edges move 20-40 px; the old +-12 px
// search around the last pose tracked none. Frames given in order are tracked from the
// motion so far (30 frames a second assumed for files).
TEST_F(CornerCliTest, TracksADriveAtOneMetreASecond) {
  DrivingPath path;
  path.speed_mps = 1.0;
  path.turn_deg_per_s = 45;
  path.start_s = 3.0;
  std::string files;
  std::vector<CornerPose> truth;
  for (int i = 0; i < 12; ++i) {
    const CornerPose p = DrivingPoseAt(path, i / 30.0);
    truth.push_back(p);
    const std::string frame = dir_ / ("drive" + std::to_string(i) + ".png");
    std::ostringstream pose;
    pose.precision(9);
    pose << p.x_m << "," << p.y_m << "," << p.z_m << "," << p.pan_rad << "," << p.tilt_rad << ","
         << p.swing_rad;
    auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" + " --pose " +
                                  pose.str() + " --realistic --seed 7 --out " + frame);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    files += " " + frame;
  }
  auto r = RunMonocle(
      dir_, "corner locate" + files + " --calibration " + dir_ / "cal.pbtxt" + " --track --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), truth.size()) << r.out;
  int tracked = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    proto::CornerOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(lines[i], &out).ok()) << lines[i];
    tracked += out.source() == "tracked";
    const double horizontal = std::hypot(truth[i].x_m, truth[i].y_m);
    EXPECT_LT(std::hypot(out.x() - truth[i].x_m, out.y() - truth[i].y_m), 0.01 * horizontal)
        << "frame " << i << ": " << lines[i];
  }
  EXPECT_EQ(tracked, 11) << "every frame after the first tracked:\n" << r.out;
}

// A calibration without the covariance of its intrinsics is said to leave it out of 1 sigma;
// with one, 1 sigma includes what it adds to the pose.
TEST_F(CornerCliTest, OneSigmaIncludesTheCalibrationsUncertaintyOrSaysItDoesNot) {
  CameraCalibration cal;
  cal.intrinsics = testing::PaperCamera();
  cal.ceiling_distance_m = 1.6;
  IntrinsicParams sigma;
  sigma << 2.0, 2.0, 3.0, 3.0, 0.01, 0.02, 0.0005, 0.0005, 0.0;
  cal.intrinsics_covariance = sigma.array().square().matrix().asDiagonal();
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "with_covariance.pbtxt", cal).ok());
  auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                " --pose 2.0,1.5,1.6,2.2143,0.9,0.1 --realistic --seed 5 --out " +
                                dir_ / "view.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::CornerOutput without, with;
  r = RunMonocle(dir_, "corner locate " + dir_ / "view.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no covariance of its intrinsics"), std::string::npos) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(Lines(r.out).at(0), &without).ok());
  EXPECT_TRUE(without.sigma_excludes_intrinsics());
  r = RunMonocle(dir_, "corner locate " + dir_ / "view.png" + " --calibration " +
                           dir_ / "with_covariance.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("no covariance"), std::string::npos) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(Lines(r.out).at(0), &with).ok());
  EXPECT_FALSE(with.sigma_excludes_intrinsics());
  EXPECT_DOUBLE_EQ(with.x(), without.x()) << "the same pose";
  EXPECT_GT(with.sigma().x(), 2 * without.sigma().x()) << "a 2 px focal error alone is ~3 mm";
}

TEST_F(CornerCliTest, TracksAnOrderedSequenceOfRealisticFrames) {
  // A robot turning slowly under a white-painted corner: four frames, one look.
  std::vector<std::string> frames;
  for (int i = 0; i < 4; ++i) {
    const std::string frame = dir_ / ("frame" + std::to_string(i) + ".png");
    const std::string pose = std::to_string(2.0 + 0.01 * i) + ",1.5,1.6," +
                             std::to_string(2.2143 + 0.004 * i) + ",0.9,0.1";
    auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" + " --pose " +
                                  pose + " --realistic --seed 3 --out " + frame);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("RealisticLook{"), std::string::npos) << "the look is printed";
    frames.push_back(frame);
  }
  std::string files;
  for (const auto& f : frames) files += " " + f;
  auto r = RunMonocle(dir_, "corner locate" + files + " --calibration " + dir_ / "cal.pbtxt" +
                                " --track --detect-every 3 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 4u) << r.out;
  const char* expected[4] = {"detected", "tracked", "tracked", "detected"};
  for (int i = 0; i < 4; ++i) {
    proto::CornerOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(lines[i], &out).ok()) << lines[i];
    EXPECT_EQ(out.source(), expected[i]) << "frame " << i;
    // A detected frame says which resolution found its Y (these, a quarter); a tracked one
    // was not searched.
    if (out.source() == "detected") {
      EXPECT_EQ(out.detection_scale(), 0.25) << lines[i];
    } else {
      EXPECT_FALSE(out.has_detection_scale()) << lines[i];
    }
    EXPECT_NEAR(out.x(), 2.0 + 0.01 * i, 0.01) << lines[i];
    EXPECT_NEAR(out.y(), 1.5, 0.01) << lines[i];
    EXPECT_FALSE(out.suspect()) << out.suspect_reason();
    ASSERT_EQ(out.lines_size(), 3);
    double shares = 0;
    for (const auto& line : out.lines()) {
      EXPECT_GT(line.contrast_to_noise(), 2) << line.axis();
      EXPECT_GT(line.coverage(), 0.3) << line.axis();
      EXPECT_GT(line.length_px(), 80) << line.axis();
      // Each edge's part of the position's variance: tracked frames as detected ones.
      EXPECT_GT(line.position_variance_share(), 0) << line.axis();
      shares += line.position_variance_share();
    }
    EXPECT_NEAR(shares, 1.0, 1e-6) << lines[i];
  }
  // Without --track every frame is detected.
  r = RunMonocle(dir_,
                 "corner locate" + files + " --calibration " + dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& line : Lines(r.out)) {
    proto::CornerOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok());
    EXPECT_EQ(out.source(), "detected");
  }
  r = RunMonocle(dir_, "corner locate" + files + " --calibration " + dir_ / "cal.pbtxt" +
                           " --track --detect-every 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--detect-every"), std::string::npos) << r.err;
}

// A far camera (5.9 m from one wall, 0.33 m from the other) fixes its position weakly: the
// JSON says how far the shading beside the edges moved it, and the 1 sigma counts that shift;
// and that its edges were measured a second time, with the wider filter (measured_again).
// A near one's pose is not looked at that way (its 1 sigma is under 0.4 % of the distance).
TEST_F(CornerCliTest, AWeakViewSaysHowFarTheShadingMovedIt) {
  const std::string far = dir_ / "far.png", near = dir_ / "near.png";
  auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                " --pose 5.917,0.333,2.681,1.8598,1.1388,0.3132 --realistic "
                                "--seed 3 --out " +
                                far);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 2,1.5,1.6,2.2143,0.9,0.1 --realistic --seed 3 --out " + near);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_, "corner locate " + far + " " + near + " --calibration " +
                           dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 2u) << r.out;
  for (int i = 0; i < 2; ++i) {
    proto::CornerOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(lines[i], &out).ok()) << lines[i];
    ASSERT_TRUE(out.has_x()) << lines[i];
    const double distance = std::hypot(out.x(), out.y());
    const double sigma = std::hypot(out.sigma().x(), out.sigma().y());
    if (i == 0) {
      EXPECT_GT(sigma, 0.004 * distance) << lines[i];
      ASSERT_EQ(out.shading_shift_m_size(), 2) << lines[i];
      EXPECT_LE(std::abs(out.shading_shift_m(0)), out.sigma().x()) << lines[i];
      EXPECT_LE(std::abs(out.shading_shift_m(1)), out.sigma().y()) << lines[i];
      // Its 1 sigma (1.7 %) is over 0.6 %: the edges were measured a second time.
      EXPECT_GT(sigma, 0.006 * distance) << lines[i];
      EXPECT_TRUE(out.measured_again()) << lines[i];
    } else {
      EXPECT_LT(sigma, 0.004 * distance) << lines[i];
      EXPECT_EQ(out.shading_shift_m_size(), 0) << lines[i];
      EXPECT_FALSE(out.has_measured_again()) << lines[i];
    }
  }
}

// A camera mounted rolled 52 degrees about its axis: beyond the default 45 every pose is
// flagged (a floor corner read as the ceiling's rolls the camera over); corner { max_swing }
// in its calibration file says how far this camera's mount may roll.
// `render corner --realistic --raw`: the same white room without the JPEG step, as a GigE or
// USB3 camera delivers frames. Both are located, and their noise (what each edge's contrast
// is judged against) is the look's sensor noise in both: JPEG removes the pixel-to-pixel
// part of the noise, not what an edge measurement averages.
TEST_F(CornerCliTest, ARawFrameReadsTheSameNoiseAsItsJpeg) {
  double sensor_noise = 0;
  std::vector<proto::CornerOutput> out(2);
  for (int raw = 0; raw < 2; ++raw) {
    const std::string image = dir_ / (raw ? "raw.png" : "jpeg.png");
    auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                  " --pose 2,1.5,1.6,2.2143,0.9,0.1 --realistic --seed 4" +
                                  (raw ? " --raw" : "") + " --out " + image);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The printed look: "..., noise 2.9, jpeg 0}" raw, "jpeg 77}" not.
    const auto noise_at = r.out.find("noise "), jpeg_at = r.out.find("jpeg ");
    ASSERT_NE(noise_at, std::string::npos) << r.out;
    ASSERT_NE(jpeg_at, std::string::npos) << r.out;
    sensor_noise = std::stod(r.out.substr(noise_at + 6));
    EXPECT_EQ(std::stoi(r.out.substr(jpeg_at + 5)) == 0, raw == 1) << r.out;
    r = RunMonocle(dir_,
                   "corner locate " + image + " --calibration " + dir_ / "cal.pbtxt" + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out[raw]).ok()) << r.out;
    EXPECT_NEAR(out[raw].x(), 2.0, 0.02) << r.out;
    EXPECT_NEAR(out[raw].noise_grey(), sensor_noise, 0.25 * sensor_noise) << r.out;
  }
  EXPECT_NEAR(out[1].noise_grey(), out[0].noise_grey(), 0.25 * out[0].noise_grey());
  // --raw is a variant of the realistic look only.
  const auto r =
      RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 2,1.5,1.6,2.2143,0.9,0.1 --raw --out " + dir_ / "x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--raw goes with --realistic"), std::string::npos) << r.err;
}

TEST_F(CornerCliTest, ACameraMountedRolledSaysSoInItsCalibration) {
  auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                " --pose 2,1.5,1.6,2.2143,0.9,0.9 --noise 2 --out " +
                                dir_ / "rolled.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::CornerOutput out;
  r = RunMonocle(dir_, "corner locate " + dir_ / "rolled.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_NEAR(out.swing(), 0.9, 0.005);
  EXPECT_TRUE(out.suspect());
  EXPECT_NE(out.suspect_reason().find("rolled"), std::string::npos) << out.suspect_reason();
  r = RunMonocle(dir_, "corner locate " + dir_ / "rolled.png" + " --calibration " +
                           dir_ / "rolled.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_NEAR(out.x(), 2.0, 0.01);
  EXPECT_NEAR(out.swing(), 0.9, 0.005);
  EXPECT_FALSE(out.suspect()) << out.suspect_reason();
}

// A mount file (CameraMount) for a camera looking ahead and up, `up_deg` from the vertical,
// upright, 0.4 m above the base's origin and 0.1 m ahead of it.
void WriteMountLookingUp(const std::string& path, double up_deg) {
  const Eigen::Quaterniond q = testing::CameraLookingUp(up_deg);
  std::ofstream(path) << std::setprecision(12) << "base_frame: \"base_link\"\n"
                      << "translation_m: [0.1, 0, 0.4]\n"
                      << "rotation_xyzw: [" << q.x() << ", " << q.y() << ", " << q.z() << ", "
                      << q.w() << "]\n";
}

// --mount without --map: the robot's level fixes the camera's tilt and swing; a mount the
// image disagrees with is said so.
TEST_F(CornerCliTest, AMountsLevelIsCombinedWithThePoseAndAWrongMountIsSuspect) {
  // A white-painted corner seen from a camera 50 degrees from the vertical, upright.
  auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                " --pose 2.5,1.2,1.6,2.3,0.872665,0 --realistic --seed 5 --out " +
                                dir_ / "up50.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  WriteMountLookingUp(dir_ / "mount50.pbtxt", 50);
  WriteMountLookingUp(dir_ / "mount53.pbtxt", 53);
  proto::CornerOutput alone, level, wrong;
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &alone).ok()) << r.out;
  EXPECT_FALSE(alone.has_level_error_deg());
  EXPECT_FALSE(alone.has_base()) << "no mount, no base";
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --mount " + dir_ / "mount50.pbtxt" +
                           " --level-sigma 0.1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &level).ok()) << r.out;
  EXPECT_LT(level.level_error_deg(), 0.2);
  EXPECT_DOUBLE_EQ(level.level_sigma_deg(), 0.1);
  EXPECT_FALSE(level.suspect()) << level.suspect_reason();
  EXPECT_NEAR(level.tilt(), 0.872665, 0.002);
  EXPECT_NEAR(level.x(), 2.5, 0.01);
  // The level is information: the tilt's 1 sigma shrinks (this view fixes its tilt to 0.015
  // degrees, so by little; the weakly determined views gain most, corner_accuracy_test).
  EXPECT_LT(level.sigma().tilt(), alone.sigma().tilt());
  EXPECT_LE(level.sigma().x(), alone.sigma().x());
  // With a mount the robot's base comes with the pose, with its 1 sigma.
  testing::ExpectBaseUnderTheCamera(level, {2.5, 1.2});
  // A mount 3 degrees off what the image shows: suspect, with how far.
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --mount " + dir_ / "mount53.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &wrong).ok()) << r.out;
  EXPECT_NEAR(wrong.level_error_deg(), 3.0, 0.2);
  EXPECT_TRUE(wrong.suspect());
  EXPECT_NE(wrong.suspect_reason().find("deg from level (allowed 1.00 deg;"), std::string::npos)
      << wrong.suspect_reason();
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --mount " + dir_ / "mount53.pbtxt");
  EXPECT_NE(r.out.find("SUSPECT"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("level 3.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" deg)  base x="), std::string::npos) << r.out;
  // Errors that say what to do.
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --mount " + dir_ / "mount50.pbtxt" +
                           " --level-sigma 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--level-sigma must be"), std::string::npos) << r.err;
  // A live camera's poses are levelled by monocled's configuration, not by this flag.
  r = RunMonocle(dir_, "corner locate --camera ceiling --mount " + dir_ / "mount50.pbtxt");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--mount and --camera do not go together: a live camera's poses come as "
                       "monocled's configuration makes them"),
            std::string::npos)
      << r.err;
  {
    std::ofstream(dir_ / "broken.pbtxt") << "base_frame: \"base_link\"\ntranslation_m: [0.1, 0]\n";
  }
  r = RunMonocle(dir_, "corner locate " + dir_ / "up50.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --mount " + dir_ / "broken.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("translation_m"), std::string::npos) << r.err;
}

// A ceiling corner has three edges. With a dark wedge painted into a realistic ceiling from
// the corner (a fourth and a fifth edge, 50 grey levels deep), the pose is suspect, the JSON
// names the strongest other edge, and the overlay draws it. (A wedge 20 grey levels deep is
// not flagged: the weakest of this view's edges reads 19 on the rings, and the flag is at
// 1.5 times; 30 is, at 29 against 18.8.)
TEST_F(CornerCliTest, AnotherEdgeLeavingTheCornerIsNamedAndDrawn) {
  const std::string image = dir_ / "wedge.png";
  auto r =
      RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                           " --pose 2,1.5,1.6,2.2143,0.9,0.1 --realistic --seed 3 --out " + image);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_,
                 "corner locate " + image + " --calibration " + dir_ / "cal.pbtxt" + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::CornerOutput clean;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &clean).ok()) << r.out;
  ASSERT_FALSE(clean.suspect()) << clean.suspect_reason();
  EXPECT_GT(clean.other_edge_step_grey(), 0) << "read on every pose";
  const cv::Point2d corner(clean.corner_px(0), clean.corner_px(1));
  // The ceiling lies between the X and Y edges; the wedge is 12 degrees wide about their
  // bisector.
  auto direction = [&](int line) {
    const auto& l = clean.lines(line);
    const cv::Point2d d(l.to_px(0) - l.from_px(0), l.to_px(1) - l.from_px(1));
    return d / std::hypot(d.x, d.y);
  };
  const cv::Point2d bisector = direction(0) + direction(1);
  const double middle = std::atan2(bisector.y, bisector.x);
  std::vector<double> wedge_rad = {middle - 6 * std::numbers::pi / 180,
                                   middle + 6 * std::numbers::pi / 180};
  cv::Mat grey = cv::imread(image, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(grey.empty());
  std::vector<cv::Point> wedge{cv::Point(corner)};
  for (double a : wedge_rad)
    wedge.push_back(cv::Point(corner + 400 * cv::Point2d(std::cos(a), std::sin(a))));
  // 50 grey levels darker than the ceiling around it; the realistic look's edges are 8-40.
  cv::Mat mask = cv::Mat::zeros(grey.size(), CV_8U);
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{wedge}, cv::Scalar(255));
  cv::subtract(grey, cv::Scalar(50), grey, mask);
  ASSERT_TRUE(cv::imwrite(image, grey));

  r = RunMonocle(dir_, "corner locate " + image + " --calibration " + dir_ / "cal.pbtxt" +
                           " --json --overlay " + dir_ / "overlays");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  proto::CornerOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_TRUE(out.suspect());
  EXPECT_NE(out.suspect_reason().find("leaves the corner"), std::string::npos)
      << out.suspect_reason();
  EXPECT_GT(out.other_edge_step_grey(), 40) << r.out;
  ASSERT_EQ(out.other_edge_towards_px_size(), 2);
  const double towards = std::atan2(out.other_edge_towards_px(1) - out.corner_px(1),
                                    out.other_edge_towards_px(0) - out.corner_px(0));
  const double off_rad =
      std::min(std::abs(std::remainder(towards - wedge_rad[0], 2 * std::numbers::pi)),
               std::abs(std::remainder(towards - wedge_rad[1], 2 * std::numbers::pi)));
  EXPECT_LT(off_rad, 2 * std::numbers::pi / 180) << "along one of the wedge's sides";
  // The overlay draws it (magenta: blue and red full, green none) near the corner.
  const cv::Mat overlay = cv::imread(dir_ / "overlays/wedge.overlay.png");
  ASSERT_FALSE(overlay.empty());
  const cv::Point2d along = corner + 60 * cv::Point2d(std::cos(towards), std::sin(towards));
  const cv::Vec3b pixel = overlay.at<cv::Vec3b>(cv::Point(along));
  EXPECT_GT(pixel[0], 200);
  EXPECT_LT(pixel[1], 60);
  EXPECT_GT(pixel[2], 200);
}

TEST_F(CornerCliTest, AViewWithoutACornerSaysWhatWasSeen) {
  // Looking along one ceiling edge from close to a wall: two edges meet, the third is out
  // of view. The message names what was found.
  auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" +
                                " --pose 3,1,1.6,1.9,0.7,-0.2 --noise 2 --out " + dir_ / "b.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_, "corner locate " + dir_ / "b.png" + " --calibration " + dir_ / "cal.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("straight edge"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// Every command's --help is its own: exit status 0, its own usage line, and no other
// command's (`render floor --help` once printed the corner help too). The commands are the
// program's own list, so a new command is checked without touching this test.
TEST(CommandLineHelpTest, EachCommandPrintsItsOwnHelp) {
  TempDir dir("monocle_help");
  const auto list = testing::RunMonocle(dir, "help --list");
  ASSERT_EQ(list.exit_code, 0) << list.err;
  std::vector<std::string> commands;
  std::istringstream names(list.out);
  for (std::string name; std::getline(names, name);) commands.push_back(name);
  for (const char* expected :
       {"floor calibrate", "corner locate", "render boards", "replay", "security init", "simcam"}) {
    EXPECT_NE(std::find(commands.begin(), commands.end(), expected), commands.end()) << expected;
  }
  const auto usage = testing::RunMonocle(dir, "--help");
  for (const std::string& command : commands) {
    EXPECT_NE(usage.out.find("\n  " + command + " "), std::string::npos)
        << command << " is missing from the top-level usage";
    const auto r = testing::RunMonocle(dir, command + " --help");
    EXPECT_EQ(r.exit_code, 0) << command;
    EXPECT_EQ(r.out.rfind("Usage: monocle " + command, 0), 0u) << command << ":\n" << r.out;
    size_t usages = 0;
    for (size_t at = r.out.find("Usage:"); at != std::string::npos;
         at = r.out.find("Usage:", at + 1))
      ++usages;
    EXPECT_EQ(usages, 1u) << command << " prints more than its own help:\n" << r.out;
  }
  const auto overview = testing::RunMonocle(dir, "render --help");
  EXPECT_EQ(overview.exit_code, 0);
  EXPECT_NE(overview.out.find("boards"), std::string::npos);
  const auto unknown = testing::RunMonocle(dir, "render nope");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown render command 'nope'"), std::string::npos) << unknown.err;
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// client/cli/README.md is what `monocle help --markdown` prints: every command's own help, so
// the page cannot drift from the program.
TEST(CommandReferenceTest, ThePageIsWhatTheProgramPrints) {
  TempDir dir("monocle_reference");
  const auto r = testing::RunMonocle(dir, "help --markdown");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream page(std::string(MONOCLE_SOURCE_DIR) + "/client/cli/README.md");
  ASSERT_TRUE(page.good());
  std::stringstream text;
  text << page.rdbuf();
  EXPECT_TRUE(text.str() == r.out)
      << "client/cli/README.md is out of step with the program; regenerate it with\n"
         "  build/client/monocle help --markdown > client/cli/README.md";
  EXPECT_NE(r.out.find("## monocle render boards"), std::string::npos);
}

}  // namespace
}  // namespace monocle
