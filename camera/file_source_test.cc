#include "camera/file_source.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace monocle {
namespace {

class FileSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_);
    for (int i = 0; i < 3; ++i) {
      cv::imwrite((dir_ / ("f" + std::to_string(i) + ".png")).string(),
                  cv::Mat(8, 8, CV_8UC1, cv::Scalar(10 * i)));
    }
    std::ofstream(dir_ / "notes.txt") << "not an image";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() / ("monocle_files_" + std::to_string(::getpid()));
};

TEST_F(FileSourceTest, ReplaysAFolderInNameOrderAndLoops) {
  auto src = FileSource::Open({dir_.string()}, /*loop=*/true);
  ASSERT_TRUE(src.ok()) << src.error();
  for (int i = 0; i < 5; ++i) {
    auto f = (*src)->Next(std::chrono::milliseconds(0));
    ASSERT_TRUE(f.ok()) << f.error();
    EXPECT_EQ(f->grey.at<uint8_t>(0, 0), 10 * (i % 3));
    EXPECT_EQ(f->sequence, static_cast<uint64_t>(i));
  }
}

TEST_F(FileSourceTest, AListEndsAndReportsUnreadableFiles) {
  auto src = FileSource::Open({(dir_ / "f1.png").string(), (dir_ / "missing.png").string()}, false);
  ASSERT_TRUE(src.ok());
  EXPECT_TRUE((*src)->Next(std::chrono::milliseconds(0)).ok());
  const auto bad = (*src)->Next(std::chrono::milliseconds(0));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("missing.png"), std::string::npos);
  EXPECT_EQ((*src)->Next(std::chrono::milliseconds(0)).error().code, ErrorCode::kNotFound);
  EXPECT_FALSE(FileSource::Open({(dir_ / "nothing").string()}, false).ok() &&
               FileSource::Open({}, false).ok());
}

}  // namespace
}  // namespace monocle
