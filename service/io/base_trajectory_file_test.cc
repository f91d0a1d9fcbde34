#include "service/io/base_trajectory_file.h"

#include <gtest/gtest.h>

#include <cmath>

namespace monocle {
namespace {

TEST(BaseTrajectoryFileTest, TheExampleDriveHasTwentyFivePosesInDegrees) {
  const auto drive =
      LoadBaseTrajectoryFile(std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/drive.txt");
  ASSERT_TRUE(drive.ok()) << drive.error();
  ASSERT_EQ(drive->size(), 25u);
  EXPECT_DOUBLE_EQ(drive->front().x_m, 1.4);
  EXPECT_DOUBLE_EQ(drive->front().y_m, 1.3);
  EXPECT_NEAR(drive->front().heading_rad, -20 * M_PI / 180, 1e-12);
  EXPECT_NEAR(drive->back().heading_rad, 60 * M_PI / 180, 1e-12);
}

TEST(BaseTrajectoryFileTest, CommasCommentsAndBlankLinesAreAccepted) {
  const auto t = ParseBaseTrajectory("# header\n\n1,2,90  # a comment\n 3 4 -45\n", "t.txt");
  ASSERT_TRUE(t.ok()) << t.error();
  ASSERT_EQ(t->size(), 2u);
  EXPECT_NEAR((*t)[0].heading_rad, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ((*t)[1].y_m, 4);
}

TEST(BaseTrajectoryFileTest, ABrokenLineIsNamedWithItsField) {
  const auto word = ParseBaseTrajectory("1 2 3\n1 2 east\n", "drive.txt");
  ASSERT_FALSE(word.ok());
  EXPECT_EQ(word.error().message, "drive.txt: line 2: heading_deg 'east' is not a number");
  const auto few = ParseBaseTrajectory("\n\n1 2\n", "drive.txt");
  ASSERT_FALSE(few.ok());
  EXPECT_EQ(few.error().message,
            "drive.txt: line 3: expected 3 numbers, x_m y_m heading_deg, found 2");
  const auto partial = ParseBaseTrajectory("1.5x 2 3\n", "drive.txt");
  ASSERT_FALSE(partial.ok());
  EXPECT_NE(partial.error().message.find("x_m '1.5x'"), std::string::npos);
  const auto empty = ParseBaseTrajectory("# nothing\n", "drive.txt");
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("no poses"), std::string::npos);
  EXPECT_FALSE(LoadBaseTrajectoryFile("/nonexistent/drive.txt").ok());
}

}  // namespace
}  // namespace monocle
