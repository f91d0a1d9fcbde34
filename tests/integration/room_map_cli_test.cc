// `monocle render room`, `monocle corner locate --map`, `monocle map check` and `map draw` as a
// user runs them, on the example map, mount, camera and drive of idl/examples/.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "idl/cli_output.pb.h"
#include "service/io/base_trajectory_file.h"
#include "tests/integration/cli_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

const std::string kExamples = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/";
const std::string kMapArgs = " --map " + kExamples + "room_map.pbtxt --mount " + kExamples +
                             "camera_mount.pbtxt --calibration " + kExamples + "wide_camera.pbtxt";

std::vector<proto::CornerOutput> ParseLines(const std::string& text) {
  std::vector<proto::CornerOutput> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) {
    proto::CornerOutput o;
    EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(line, &o).ok()) << line;
    out.push_back(o);
  }
  return out;
}

class RoomMapCliTest : public ::testing::Test {
 protected:
  TempDir dir_{"monocle_room_map_cli"};
};

TEST_F(RoomMapCliTest, ADriveRenderedAlongATrajectoryIsLocatedInTheMapAndDrawn) {
  // A seed this test alone uses: the realistic look of frame k is drawn from 3100 + k.
  auto r = RunMonocle(dir_, "render room" + kMapArgs + " --trajectory " + kExamples +
                                "drive.txt --realistic --seed 3100 --out " + dir_ / "frames");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto truth = LoadBaseTrajectoryFile(kExamples + "drive.txt");
  ASSERT_TRUE(truth.ok());
  std::string images;
  for (size_t i = 0; i < truth->size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    ASSERT_TRUE(std::filesystem::exists(dir_ / ("frames/" + std::string(name)))) << name;
    images += " " + dir_ / ("frames/" + std::string(name));
  }

  // In order, from the known start: each located pose is the next one's prior.
  r = RunMonocle(dir_, "corner locate" + images + kMapArgs + " --track --prior 1.4,1.3,-20 --json");
  const auto out = ParseLines(r.out);
  ASSERT_EQ(out.size(), truth->size()) << r.err;
  int located = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!out[i].has_map()) {
      EXPECT_TRUE(out[i].has_error()) << "frame " << i << ": neither a corner nor an error";
      continue;
    }
    const auto& m = out[i].map();
    ASSERT_EQ(m.status(), "located") << "frame " << i << ": " << m.reason();
    ++located;
    const auto& t = (*truth)[i];
    // Within the corner goals: 1 % of a distance of at most 6 m, and the heading.
    EXPECT_LT(std::hypot(m.pose().x() - t.x_m, m.pose().y() - t.y_m), 0.06) << "frame " << i;
    EXPECT_LT(std::abs(std::remainder(m.pose().heading_deg() - t.heading_rad * 180 / M_PI, 360)),
              0.5)
        << "frame " << i;
    EXPECT_TRUE(m.pose().corner() == "hall-1" || m.pose().corner() == "hall-2")
        << "frame " << i << ": the drive looks east, at the corners of the east wall, not "
        << m.pose().corner();
    EXPECT_GT(m.pose().sigma().x(), 0);
    ASSERT_EQ(m.pose().camera_position_size(), 3);
    EXPECT_NEAR(m.pose().camera_position(2), 0.4, 0.02) << "the mount's height";
  }
  EXPECT_GE(located, 18) << "of " << out.size() << " frames";
  EXPECT_EQ(r.exit_code, located == static_cast<int>(out.size()) ? 0 : 1);

  // The first frame alone, without a prior: decided only if the room decides it; never a
  // wrong guess.
  r = RunMonocle(dir_, "corner locate " + dir_ / "frames/frame_0000.png" + kMapArgs + " --json");
  const auto alone = ParseLines(r.out);
  ASSERT_EQ(alone.size(), 1u);
  if (alone[0].map().status() == "located") {
    EXPECT_LT(std::hypot(alone[0].map().pose().x() - 1.4, alone[0].map().pose().y() - 1.3), 0.06);
  } else {
    EXPECT_EQ(alone[0].map().status(), "ambiguous") << alone[0].map().reason();
    EXPECT_GE(alone[0].map().candidates_size(), 2);
    EXPECT_NE(alone[0].map().reason().find("--prior"), std::string::npos) << "says what to do";
    EXPECT_EQ(r.exit_code, 1);
  }
  // Text output names the corner and the base pose with units.
  r = RunMonocle(
      dir_, "corner locate " + dir_ / "frames/frame_0003.png" + kMapArgs + " --prior 2.0,1.33,-16");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("map: hall-"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" m heading="), std::string::npos) << r.out;

  // The picture: the map with the path and the poses, poses joined to their corners.
  r = RunMonocle(dir_, "corner locate" + images + kMapArgs + " --track --prior 1.4,1.3,-20 --json");
  { std::ofstream(dir_ / "poses.jsonl") << r.out; }
  r = RunMonocle(dir_, "map draw " + kExamples + "room_map.pbtxt --trajectory " + kExamples +
                           "drive.txt --poses " + dir_ / "poses.jsonl" + " --out " +
                           dir_ / "map.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const cv::Mat picture = cv::imread(dir_ / "map.png");
  ASSERT_FALSE(picture.empty());
  EXPECT_GE(picture.cols, 800);
}

TEST_F(RoomMapCliTest, BadFilesAndArgumentsAreRefusedWithWhatToDo) {
  // A map whose corner lies outside its room: the line and the field.
  {
    std::ofstream(dir_ / "bad_map.pbtxt")
        << "room {\n  id: \"r\"\n  ceiling_height_m: 2.5\n"
           "  outline { x_m: 0 y_m: 0 } outline { x_m: 4 y_m: 0 }\n"
           "  outline { x_m: 4 y_m: 4 } outline { x_m: 0 y_m: 4 }\n"
           "  corner { id: \"c\" position { x_m: 6 y_m: 1 } }\n}\n";
  }
  auto r = RunMonocle(dir_, "map check " + dir_ / "bad_map.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad_map.pbtxt: line 6: room[0].corner[0].position lies outside the room"),
            std::string::npos)
      << r.err;
  // A camera mounted above the ceiling.
  {
    std::ofstream(dir_ / "high.pbtxt")
        << "translation_m: [0, 0, 3.0]\nrotation_xyzw: [0, 0, 0, 1]\n";
  }
  r = RunMonocle(dir_, "map check " + kExamples + "room_map.pbtxt --mount " + dir_ / "high.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("high.pbtxt: line 1: translation_m[2] puts the camera 3 m above the floor"),
            std::string::npos)
      << r.err;
  // The good examples pass and are explained.
  r = RunMonocle(dir_, "map check " + kExamples + "room_map.pbtxt --mount " + kExamples +
                           "camera_mount.pbtxt");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("corner hall-1 at (7.00, 0.00) m"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ceiling distance 2.20 m"), std::string::npos) << r.out;
  // --map without --mount; a broken poses file; a pose outside every room.
  r = RunMonocle(dir_, "corner locate x.png --calibration " + kExamples +
                           "wide_camera.pbtxt --map " + kExamples + "room_map.pbtxt");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--map needs --mount"), std::string::npos) << r.err;
  { std::ofstream(dir_ / "poses.jsonl") << "{\"image\": \"a.png\"}\n{\"image\": 3, \n"; }
  r = RunMonocle(dir_, "map draw " + kExamples + "room_map.pbtxt --poses " + dir_ / "poses.jsonl" +
                           " --out " + dir_ / "m.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("poses.jsonl: line 2: not a line of `monocle corner locate --map --json`"),
            std::string::npos)
      << r.err;
  r = RunMonocle(dir_, "render room" + kMapArgs + " --pose 7.5,1,0 --out " + dir_ / "x.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("stands in no room of the map"), std::string::npos) << r.err;
}

// The CameraMount text of a camera looking ahead and up, `up_deg` from the vertical, rolled
// `roll_deg` about its optical axis (written from the geometry here, not monocle's code), and
// its rotation.
Eigen::Quaterniond LookingUp(double up_deg, double roll_deg) {
  const double t = up_deg * M_PI / 180;
  const Eigen::Vector3d z(std::sin(t), 0, std::cos(t)), x(0, -1, 0);
  Eigen::Matrix3d r;
  r << x, z.cross(x), z;
  return Eigen::Quaterniond(r * Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitZ()));
}
std::string MountText(const Eigen::Quaterniond& q) {
  std::ostringstream text;
  text << std::setprecision(12) << "base_frame: \"base_link\"\ntranslation_m: [0.1, 0, 0.4]\n"
       << "rotation_xyzw: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
  return text.str();
}

// A user fits the mount's level: the robot stands at places around the example hall facing
// its corners (the mount of idl/examples, 50 degrees up), the images rendered as its camera
// sees them; the mount configured is 1 degree too steep and rolled 0.5 degrees. The fit finds
// that error (a roll about the optical axis is 0.5 sin 50 degrees about the base's x axis;
// its part about the vertical, the heading, is not the level's), writes a mount whose up axis
// is the true one's, and finds the rendered floor level.
TEST_F(RoomMapCliTest, TheMountsLevelIsFittedFromImagesAroundTheHall) {
  {
    std::ofstream tour(dir_ / "tour.txt");
    const std::vector<std::array<double, 2>> spots = {{1.5, 1.5}, {2.5, 1.0}, {4.5, 1.5},
                                                      {5.5, 1.2}, {1.2, 3.8}, {2.0, 2.5}};
    const std::vector<std::array<double, 2>> corners = {{0, 0}, {7, 0}, {7, 3}, {0, 5}};
    for (const auto& [x, y] : spots) {
      for (const auto& [cx, cy] : corners) {
        const double d = std::hypot(cx - x, cy - y);
        if (d < 1.5 || d > 5.5 || (cx == 0 && cy == 5 && x > 3)) continue;
        tour << x << " " << y << " " << std::atan2(cy - y, cx - x) * 180 / M_PI << "\n";
      }
    }
  }
  auto r = RunMonocle(dir_, "render room" + kMapArgs + " --trajectory " + dir_ / "tour.txt" +
                                " --realistic --seed 4100 --out " + dir_ / "frames");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string images;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "frames"))
    images += " " + entry.path().string();
  const Eigen::Quaterniond truth = LookingUp(50, 0);
  { std::ofstream(dir_ / "wrong.pbtxt") << MountText(LookingUp(51, 0.5)); }
  const std::string fit = "corner fit-mount" + images + " --calibration " + kExamples +
                          "wide_camera.pbtxt --ceiling-distance 2.2 --mount ";
  r = RunMonocle(dir_, fit + dir_ / "wrong.pbtxt --out " + dir_ / "fitted.pbtxt --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  proto::MountFitOutput out;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_GE(out.used(), 12u) << r.out;
  EXPECT_NEAR(out.correction_x_deg(), -0.5 * std::sin(50 * M_PI / 180), 0.05) << r.out;
  EXPECT_NEAR(out.correction_y_deg(), -1.0, 0.05) << r.out;
  EXPECT_LT(out.sigma_x_deg(), 0.02);
  EXPECT_LT(out.floor_sigma_deg(), 0.05) << "the rendered floor is level";
  EXPECT_EQ(out.written(), dir_ / "fitted.pbtxt");
  // The written mount is a mount monocle reads, its up axis the true one's.
  r = RunMonocle(dir_,
                 "map check " + kExamples + "room_map.pbtxt --mount " + dir_ / "fitted.pbtxt");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(out.rotation_xyzw_size(), 4);
  const Eigen::Quaterniond fitted(out.rotation_xyzw(3), out.rotation_xyzw(0), out.rotation_xyzw(1),
                                  out.rotation_xyzw(2));
  const Eigen::Vector3d up_fitted = fitted.inverse() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_true = truth.inverse() * Eigen::Vector3d::UnitZ();
  EXPECT_LT(std::acos(std::min(1.0, up_fitted.dot(up_true))) * 180 / M_PI, 0.05);
  // Told the true mount, it finds nothing to correct.
  { std::ofstream(dir_ / "true.pbtxt") << MountText(truth); }
  r = RunMonocle(dir_, fit + dir_ / "true.pbtxt --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  EXPECT_LT(std::hypot(out.correction_x_deg(), out.correction_y_deg()), 0.05) << r.out;
  // Too few images: what each gave.
  r = RunMonocle(dir_, "corner fit-mount " + dir_ / "frames/frame_0000.png " +
                           dir_ / "nothing.png" + " --calibration " + kExamples +
                           "wide_camera.pbtxt --ceiling-distance 2.2 --mount " +
                           dir_ / "true.pbtxt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("needs at least 5 corner poses (got 1): 2 images gave 1 usable poses"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("nothing.png: cannot read"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace monocle
