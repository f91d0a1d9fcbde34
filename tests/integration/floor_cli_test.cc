// The offline floor tools as a user runs them: real processes, real files.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <fstream>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "idl/cli_output.pb.h"
#include "service/geometry/floor_model.h"
#include "service/geometry/test_scenes.h"
#include "service/io/calibration_file.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::Deg;
using testing::ProcessResult;
using testing::ReadFile;
using testing::RunMonocle;
using testing::TempDir;

const FloorPose kTruth{1.05, Deg(118), Deg(4), Deg(1.5)};

class FloorCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    CameraCalibration truth;
    truth.intrinsics = testing::PaperCamera();
    truth.floor = FloorCalibration{};
    truth.floor->pose = kTruth;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "truth.pbtxt", truth).ok());
    CameraCalibration intrinsics_only;
    intrinsics_only.intrinsics = truth.intrinsics;
    ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "cal.pbtxt", intrinsics_only).ok());
    const auto r = RunMonocle(
        dir_, "render floor --calibration " + dir_ / "truth.pbtxt" +
                  " --board 11x8 --square 0.05 --noise 2 --box 0.4,2.4,0.3,0.3,0.5 --out " +
                  dir_ / "board.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }

  TempDir dir_{"monocle_floor_cli"};
};

// --square in centimetres puts the camera 100x higher: refused, the likely slip named, nothing
// written; --force keeps it.
TEST_F(FloorCliTest, ASquareInTheWrongUnitIsRefusedAndNamed) {
  const std::string calibrate = "floor calibrate " + dir_ / "board.png" + " --calibration " +
                                dir_ / "cal.pbtxt" + " --board 11x8 --square 5 --write";
  const std::string before = testing::ReadFile(dir_ / "cal.pbtxt");
  auto r = RunMonocle(dir_, calibrate);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find("m above the floor is no robot's"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("If the square is 5 cm, give --square 0.05 (height 1.05"), std::string::npos)
      << r.err;
  EXPECT_EQ(testing::ReadFile(dir_ / "cal.pbtxt"), before) << "nothing written";
  r = RunMonocle(dir_, calibrate + " --force");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::ReadFile(dir_ / "cal.pbtxt"), before);
}

// A calibration file in the papers' millimetres: the limit and the likely unit are said.
TEST_F(FloorCliTest, AHeightInMillimetresIsNamed) {
  std::string text = testing::ReadFile(dir_ / "truth.pbtxt");
  const auto at = text.find("height: ", text.find("floor {"));
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, text.find('\n', at) - at, "height: 1013.0");
  std::ofstream(dir_ / "mm.pbtxt") << text;
  const auto r = RunMonocle(dir_, "floor measure --calibration " + dir_ / "mm.pbtxt" + " 640,800");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("field 'floor.height' must be the optical centre's height above the floor "
                       "in metres, more than 0 and at most 1000; 1013 reads like millimetres: "
                       "1.013 m"),
            std::string::npos)
      << r.err;
}

TEST_F(FloorCliTest, CalibrateWritesTheFileAndMeasureReadsIt) {
  // What an earlier write killed half-way (SIGKILL) left: its temporary goes with this write.
  std::ofstream(dir_ / ".cal.pbtxt.Q1w2E3") << "intrinsics {";
  const auto cal =
      RunMonocle(dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --board 11x8 --square 0.05 --write --json");
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  proto::FloorCalibrationOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(cal.out, &out).ok()) << cal.out;
  EXPECT_NEAR(out.height(), kTruth.height_m, 0.002 * kTruth.height_m);
  EXPECT_NEAR(out.pitch(), kTruth.pitch_rad, Deg(0.03));
  EXPECT_NEAR(out.yaw(), kTruth.yaw_rad, Deg(0.05));
  EXPECT_NEAR(out.roll(), kTruth.roll_rad, Deg(0.05));
  EXPECT_GT(out.sigma().height(), 0);
  EXPECT_LT(out.rms_px(), 0.2);
  EXPECT_EQ(out.method(), "full");
  EXPECT_FALSE(std::filesystem::exists(dir_ / ".cal.pbtxt.Q1w2E3")) << "a killed write's temporary";
  const auto written = LoadCalibrationFile(dir_ / "cal.pbtxt");
  ASSERT_TRUE(written.ok()) << written.error();
  ASSERT_TRUE(written->floor.has_value());
  EXPECT_DOUBLE_EQ(written->floor->pose.height_m, out.height());

  // Points projected from the ground truth: a floor point and a box corner above it.
  const auto k = testing::PaperCamera();
  const Eigen::Vector3d floor_point(0.25, 2.25, 0), top_point(0.25, 2.25, 0.5);
  const auto f = *ProjectRobotPoint(k, kTruth, floor_point);
  const auto t = *ProjectRobotPoint(k, kTruth, top_point);
  std::ostringstream args;
  args.precision(10);
  args << "floor measure --calibration " << dir_ / "cal.pbtxt"
       << " --json " << f.x() << "," << f.y() << " " << t.x() << "," << t.y() << "@" << f.x() << ","
       << f.y();
  const ProcessResult m = RunMonocle(dir_, args.str());
  EXPECT_EQ(m.exit_code, 0) << m.err;
  google::protobuf::ListValue list;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(m.out, &list).ok()) << m.out;
  ASSERT_EQ(list.values_size(), 2);
  const auto& p0 = list.values(0).struct_value().fields();
  EXPECT_NEAR(p0.at("x").number_value(), floor_point.x(), 1e-3 * floor_point.norm());
  EXPECT_NEAR(p0.at("y").number_value(), floor_point.y(), 1e-3 * floor_point.norm());
  EXPECT_EQ(p0.at("z").number_value(), 0);
  EXPECT_GT(p0.at("sigma").struct_value().fields().at("y").number_value(), 0);
  const auto& p1 = list.values(1).struct_value().fields();
  EXPECT_NEAR(p1.at("z").number_value(), top_point.z(), 0.005 * top_point.z());
}

TEST_F(FloorCliTest, PointAboveTheHorizonIsAnErrorEntryAndFailsTheCommand) {
  // A nearly level camera: the top rows of its image see the wall, not the floor.
  CameraCalibration level;
  level.intrinsics = testing::PaperCamera();
  level.floor = FloorCalibration{};
  level.floor->pose = FloorPose{1.0, Deg(97), 0, 0};
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir_ / "level.pbtxt", level).ok());
  const ProcessResult m = RunMonocle(
      dir_, "floor measure --calibration " + dir_ / "level.pbtxt" + " --json 640,900 640,2");
  EXPECT_EQ(m.exit_code, 1);
  google::protobuf::ListValue list;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(m.out, &list).ok()) << m.out;
  ASSERT_EQ(list.values_size(), 2);
  EXPECT_TRUE(list.values(0).struct_value().fields().count("y"));
  const auto& p1 = list.values(1).struct_value().fields();
  ASSERT_TRUE(p1.count("error"));
  EXPECT_NE(p1.at("error").string_value().find("horizon"), std::string::npos);
  EXPECT_FALSE(p1.count("x"));
}

TEST_F(FloorCliTest, PaperMethodExplainsItsIllConditionedSolveAndWritesNothing) {
  // An 11x8 board of 5 cm squares 2.2 m away: the paper's linear solve is biased far off by
  // the corners' noise (and the camera's 1.5 deg roll), the full method is not.
  const std::string before = ReadFile(dir_ / "cal.pbtxt");
  const auto cal = RunMonocle(
      dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " + dir_ / "cal.pbtxt" +
                " --board 11x8 --square 0.05 --method paper --write --json");
  EXPECT_EQ(cal.exit_code, 1) << cal.err;
  EXPECT_NE(cal.err.find("ill-conditioned"), std::string::npos) << cal.err;
  EXPECT_NE(cal.err.find("left unchanged"), std::string::npos) << cal.err;
  proto::FloorCalibrationOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(cal.out, &out).ok()) << cal.out;
  EXPECT_EQ(out.method(), "paper");
  EXPECT_EQ(out.roll(), 0);
  EXPECT_TRUE(out.ill_conditioned());
  EXPECT_NE(out.explanation().find("--method full"), std::string::npos) << out.explanation();
  EXPECT_NE(out.explanation().find("roll"), std::string::npos) << out.explanation();
  EXPECT_TRUE(out.written().empty());
  EXPECT_EQ(ReadFile(dir_ / "cal.pbtxt"), before);
  // Printed for a person: the explanation, and no error bar pretending to be one.
  const auto text =
      RunMonocle(dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " +
                           dir_ / "cal.pbtxt" + " --board 11x8 --square 0.05 --method paper");
  EXPECT_NE(text.out.find("not determined"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("± "), std::string::npos) << text.out;
}

TEST_F(FloorCliTest, TargetSigmaGuidanceAndOverlay) {
  const std::string overlay = dir_ / "check.png";
  // 0.1 mm at 4 m: beyond any board for 0.5 px query pixels; 5 cm at 2 m: met easily.
  auto r = RunMonocle(dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " +
                                dir_ / "cal.pbtxt" +
                                " --board 11x8 --square 0.05 --target-sigma 0.0001@4 --json "
                                "--overlay " +
                                overlay);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::FloorCalibrationOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_FALSE(out.ill_conditioned());
  EXPECT_FALSE(out.target_met());
  EXPECT_DOUBLE_EQ(out.target_distance(), 4);
  ASSERT_GT(out.advice_size(), 0);
  EXPECT_NE(out.advice(0).find("no board can"), std::string::npos) << out.advice(0);
  ASSERT_EQ(out.accuracy_size(), 3);  // 1, 2 and 4 m
  EXPECT_LT(out.accuracy(0).sigma(), out.accuracy(2).sigma());
  // The renderer centres the board where the optical axis meets the floor.
  const double axis_ground_m = kTruth.height_m / std::tan(kTruth.pitch_rad - Deg(90));
  EXPECT_NEAR(out.board().distance(), std::hypot(axis_ground_m, kTruth.height_m), 0.1);
  EXPECT_EQ(out.overlay(), overlay);

  // The picture: the image's size, in colour, corners drawn green where the board is.
  const cv::Mat picture = cv::imread(overlay, cv::IMREAD_COLOR);
  ASSERT_FALSE(picture.empty());
  EXPECT_EQ(picture.cols, 1280);
  EXPECT_EQ(picture.rows, 1024);
  const auto k = testing::PaperCamera();
  const Eigen::Vector2d corner(k.cx, k.cy);  // the board's middle
  int green = 0;
  for (int dy = -40; dy <= 40; ++dy) {
    for (int dx = -40; dx <= 40; ++dx) {
      const auto p = picture.at<cv::Vec3b>(static_cast<int>(corner.y()) + dy,
                                           static_cast<int>(corner.x()) + dx);
      green += p[1] > 150 && p[0] < 80 && p[2] < 80;
    }
  }
  EXPECT_GT(green, 20);

  r = RunMonocle(dir_, "floor calibrate " + dir_ / "board.png" + " --calibration " +
                           dir_ / "cal.pbtxt" +
                           " --board 11x8 --square 0.05 --target-sigma 0.05@2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(": met"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("advice"), std::string::npos) << r.out;
}

// Every bad input: a clear message, a non-zero exit, and the calibration file untouched.
struct BadInput {
  std::string name;
  std::string args;  // {dir} is replaced by the test directory
  int exit_code;
  std::string message;
};

class FloorCliBadInputTest : public FloorCliTest, public ::testing::WithParamInterface<BadInput> {};

TEST_P(FloorCliBadInputTest, FailsClearlyAndWritesNothing) {
  // Prepare the special inputs some cases need.
  cv::imwrite(dir_ / "blank.png", cv::Mat(1024, 1280, CV_8UC1, cv::Scalar(128)));
  cv::Mat board = cv::imread(dir_ / "board.png", cv::IMREAD_GRAYSCALE), upside_down;
  cv::rotate(board, upside_down, cv::ROTATE_180);
  cv::imwrite(dir_ / "upside_down.png", upside_down);
  { std::ofstream(dir_ / "garbage.png") << "not an image"; }
  {
    std::ofstream(dir_ / "broken.pbtxt")
        << "intrinsics { width: 1280 height: 1024\n fx: 1600 fy: 1600 cx: 640 cy: 512 focal: 3 }\n";
  }
  const std::string before = ReadFile(dir_ / "cal.pbtxt");

  std::string args = GetParam().args;
  for (size_t pos; (pos = args.find("{dir}")) != std::string::npos;)
    args.replace(pos, 5, dir_.path().string());
  const ProcessResult r = RunMonocle(dir_, args);
  EXPECT_EQ(r.exit_code, GetParam().exit_code) << r.err;
  EXPECT_NE(r.err.find(GetParam().message), std::string::npos) << r.err;
  EXPECT_EQ(ReadFile(dir_ / "cal.pbtxt"), before);
}

const std::string kCalibrate =
    "floor calibrate --calibration {dir}/cal.pbtxt --board 11x8 --square 0.05 --write ";

INSTANTIATE_TEST_SUITE_P(
    Cases, FloorCliBadInputTest,
    ::testing::Values(
        BadInput{"MissingImage", kCalibrate + "{dir}/nope.png", 1, "no such file"},
        BadInput{"UnreadableImage", kCalibrate + "{dir}/garbage.png", 1, "not an image format"},
        BadInput{"NoBoard", kCalibrate + "{dir}/blank.png", 1, "no 11x8 chessboard"},
        BadInput{"WrongBoardSize",
                 "floor calibrate --calibration {dir}/cal.pbtxt --board 10x8 --square 0.05 --write "
                 "{dir}/board.png",
                 1, "no 10x8 chessboard"},
        BadInput{"UpsideDownIsDegenerate", kCalibrate + "{dir}/upside_down.png", 1, "upside down"},
        BadInput{"BadBoardSpec",
                 "floor calibrate --calibration {dir}/cal.pbtxt --board 11by8 --square 0.05 "
                 "--write {dir}/board.png",
                 2, "COLSxROWS"},
        BadInput{"BadSquare",
                 "floor calibrate --calibration {dir}/cal.pbtxt --board 11x8 --square -1 --write "
                 "{dir}/board.png",
                 2, "--square"},
        BadInput{"BrokenCalibrationFile",
                 "floor calibrate --calibration {dir}/broken.pbtxt --board 11x8 --square 0.05 "
                 "--write {dir}/board.png",
                 1, "line 2"},
        BadInput{"MalformedPoint", "floor measure --calibration {dir}/truth.pbtxt 640,800 12,ab", 2,
                 "POINT '12,ab'"},
        BadInput{"MalformedPairedPoint",
                 "floor measure --calibration {dir}/truth.pbtxt 640,500@640", 2, "u,v@fu,fv"},
        BadInput{"NoPoints", "floor measure --calibration {dir}/truth.pbtxt", 2,
                 "takes at least 1 POINT"},
        BadInput{"MeasureWithoutFloorSection",
                 "floor measure --calibration {dir}/cal.pbtxt 640,800", 1, "no floor section"},
        BadInput{"PointOutsideImage", "floor measure --calibration {dir}/truth.pbtxt 5000,800", 1,
                 ""},
        BadInput{"UnknownOption", "floor measure --calibraton {dir}/truth.pbtxt 640,800", 2,
                 "unknown option --calibraton"}),
    [](const auto& info) { return info.param.name; });

TEST(IntrinsicsCliTest, RecoversTheCameraFromRenderedViewsWithItsSigma) {
  TempDir dir("monocle_intrinsics_cli");
  CameraCalibration truth;
  truth.intrinsics = testing::PaperCamera();
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir / "truth.pbtxt", truth).ok());
  auto r = RunMonocle(dir, "render boards --calibration " + dir / "truth.pbtxt" +
                               " --board 9x6 --square 0.04 --views 12 --seed 21 --out-dir " +
                               dir / "views");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // An existing file with a floor section: the floor must go, the corner section stays.
  CameraCalibration old = truth;
  old.floor = FloorCalibration{};
  old.floor->pose = FloorPose{1.0, Deg(120), 0, 0};
  old.ceiling_distance_m = 1.5;
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir / "cal.pbtxt", old).ok());
  std::string args = "intrinsics calibrate --board 9x6 --square 0.04 --json --out " +
                     dir / "cal.pbtxt" + " --overlay " + dir / "overlay" + " --corners " +
                     dir / "corners.vnl";
  for (int i = 1; i <= 12; ++i) {
    std::ostringstream name;
    name << "views/view-" << std::setw(2) << std::setfill('0') << i << ".png";
    args += " " + dir / name.str();
  }
  // As text, with the radial-only model: the terms it does not fit say so, not "0 ± 0".
  r = RunMonocle(dir, args.substr(0, args.find(" --json")) + " --model k1k2 --out " +
                          dir / "k1k2.pbtxt" + args.substr(args.find(" --overlay")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("k3          0.00000 (fixed: not in the k1k2 model)"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("0.00000 ± 0.00000"), std::string::npos) << r.out;
  r = RunMonocle(dir, args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("floor section"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\"model\":\"k1k2p1p2\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"floor_removed\":true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"tilt_deg\""), std::string::npos) << r.out;
  const auto got = LoadCalibrationFile(dir / "cal.pbtxt");
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_FALSE(got->floor.has_value());
  EXPECT_EQ(got->ceiling_distance_m, 1.5);
  EXPECT_EQ(got->distortion_model, "k1k2p1p2");
  const auto& k = got->intrinsics;
  const auto& t = truth.intrinsics;
  const IntrinsicsCovariance& cov = got->intrinsics_covariance;
  // Within 4 sigma of the truth, and the sigma itself plausible (not zero, not huge).
  const double errors[4] = {k.fx - t.fx, k.fy - t.fy, k.cx - t.cx, k.cy - t.cy};
  for (int p = 0; p < 4; ++p) {
    const double sigma = std::sqrt(cov(p, p));
    EXPECT_GT(sigma, 0.05) << kIntrinsicParamNames[p];
    EXPECT_LT(sigma, 5.0) << kIntrinsicParamNames[p];
    EXPECT_LT(std::abs(errors[p]), 4 * sigma) << kIntrinsicParamNames[p];
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "overlay/coverage.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "overlay/view-07.png"));
  // The JSON keeps both figures behind the 1 sigma: the analytic one and the jackknife's
  // (12 views); the 1 sigma reported, and written, is never below the analytic one.
  proto::IntrinsicsOutput json;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &json).ok()) << r.out;
  EXPECT_NE(json.covariance_method().find("jackknife"), std::string::npos);
  const double reported[4] = {json.sigma().fx(), json.sigma().fy(), json.sigma().cx(),
                              json.sigma().cy()};
  const double analytic[4] = {json.analytic_sigma().fx(), json.analytic_sigma().fy(),
                              json.analytic_sigma().cx(), json.analytic_sigma().cy()};
  const double jackknife[4] = {json.jackknife_sigma().fx(), json.jackknife_sigma().fy(),
                               json.jackknife_sigma().cx(), json.jackknife_sigma().cy()};
  for (int p = 0; p < 4; ++p) {
    EXPECT_GT(analytic[p], 0) << kIntrinsicParamNames[p];
    EXPECT_GT(jackknife[p], 0) << kIntrinsicParamNames[p];
    EXPECT_GE(reported[p], analytic[p]) << kIntrinsicParamNames[p];
    EXPECT_NEAR(reported[p], std::sqrt(cov(p, p)), 1e-4 * reported[p]) << kIntrinsicParamNames[p];
  }

  // How sure it is where a ray lands: everywhere at least what the principal point's 1 sigma
  // says (absolute), far less at the centre once the camera's rotation is out (relative), and
  // worst away from the centre; the picture of it.
  const auto& projection = json.projection_sigma();
  const auto& relative = json.relative_projection_sigma();
  EXPECT_GE(projection.centre_px(), 0.99 * std::max(reported[2], reported[3]));
  EXPECT_LE(projection.median_px(), projection.worst_px());
  EXPECT_LT(relative.centre_px(), 0.5 * projection.centre_px());
  EXPECT_GT(relative.worst_px(), 2 * relative.centre_px());
  EXPECT_GT(std::hypot(relative.worst_x() - 640, relative.worst_y() - 512), 300);
  EXPECT_TRUE(std::filesystem::exists(dir / "overlay/uncertainty.png"));
  // Every model was fitted; a model predicts the views it did not see worse than those it did.
  ASSERT_EQ(json.trials_size(), 3);
  for (const auto& trial : json.trials()) {
    EXPECT_GT(trial.held_out_rms_px(), trial.rms_px()) << trial.model();
    EXPECT_LT(trial.held_out_rms_px(), 2 * trial.rms_px()) << trial.model();
  }
  // The corners in mrcal's format: a header, then 54 lines per view, "file x y level".
  std::istringstream vnl(testing::ReadFile(dir / "corners.vnl"));
  std::string line;
  int corners = 0;
  std::getline(vnl, line);
  EXPECT_EQ(line, "# filename x y level");
  while (std::getline(vnl, line)) {
    std::istringstream fields(line);
    std::string file, x, y, level;
    fields >> file >> x >> y >> level;
    EXPECT_EQ(file.rfind("view-", 0), 0u) << line;
    EXPECT_TRUE(level == "0" || level == "-") << line;
    ++corners;
  }
  EXPECT_EQ(corners, 12 * 54);

  // Too few images is a usage error; a bad model name too.
  r = RunMonocle(dir, "intrinsics calibrate --board 9x6 --square 0.04 --out " + dir / "x.pbtxt" +
                          " " + dir / "views/view-01.png");
  EXPECT_EQ(r.exit_code, 2);
  r = RunMonocle(dir, "intrinsics calibrate --model k9 --board 9x6 --square 0.04 --out " +
                          dir / "x.pbtxt" + " a.png b.png c.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not one of auto"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// Long work draws a progress line on a terminal (a pseudo-terminal from util-linux's
// `script`) and nothing when its output goes to a file or a pipe.
TEST(ProgressLineTest, DrawnOnATerminalOnly) {
  TempDir dir("monocle_progress");
  CameraCalibration truth;
  truth.intrinsics = testing::SmallWideAngleCamera();
  ASSERT_TRUE(SaveCalibrationFileAtomically(dir / "truth.pbtxt", truth).ok());
  const std::string render = testing::MonocleBinary() + " render boards --calibration " +
                             dir / "truth.pbtxt" + " --board 7x5 --square 0.03 --views 4 --seed 3";
  // On a terminal: the line, with its count and percentage.
  const std::string on_tty = "script -qefc '" + render + " --out-dir " + dir / "tty" + "' " +
                             dir / "typescript" + " > " + dir / "tty.txt" + " 2>&1";
  ASSERT_EQ(std::system(on_tty.c_str()), 0) << testing::ReadFile(dir / "tty.txt");
  const std::string tty = testing::ReadFile(dir / "tty.txt");
  EXPECT_NE(tty.find("rendering views 0/4 (0 %)"), std::string::npos) << tty;
  EXPECT_NE(tty.find("wrote 4 views"), std::string::npos) << tty;
  // Not a terminal: no progress at all.
  const auto plain = RunMonocle(
      dir, "render boards --calibration " + dir / "truth.pbtxt" +
               " --board 7x5 --square 0.03 --views 4 --seed 3 --out-dir " + dir / "plain");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.err.find("rendering"), std::string::npos) << plain.err;

  std::string images;
  for (int i = 1; i <= 4; ++i) images += " " + dir / ("tty/view-0" + std::to_string(i) + ".png");
  const std::string calibrate = testing::MonocleBinary() +
                                " intrinsics calibrate --board 7x5 --square 0.03 --out " +
                                dir / "cal.pbtxt" + images;
  const std::string calibrate_tty =
      "script -qefc '" + calibrate + "' " + dir / "typescript" + " > " + dir / "cal.txt" + " 2>&1";
  std::system(calibrate_tty.c_str());  // four views may be too few to converge: the line counts
  const std::string cal = testing::ReadFile(dir / "cal.txt");
  EXPECT_NE(cal.find("detecting boards 0/4"), std::string::npos) << cal;
  EXPECT_NE(cal.find("calibrating from"), std::string::npos) << cal;
}

}  // namespace
}  // namespace monocle
