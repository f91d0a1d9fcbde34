// Files a user names: only regular files under a limit are read, and images are refused by
// their header's size before anything is decoded.
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <tuple>

#include "service/io/bounded_file.h"
#include "service/io/image_file.h"

namespace monocle {
namespace {

namespace fs = std::filesystem;

class BoundedFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("monocle_bounded_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& bytes) {
    const auto path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  fs::path dir_;
};

// Peak resident memory of this process, in MB (ru_maxrss is in kB on Linux).
double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

TEST_F(BoundedFileTest, ReadsARegularFile) {
  const auto text = ReadBoundedFile(Write("a.pbtxt", "domain: 3\n"), "configuration file", 100);
  ASSERT_TRUE(text.ok()) << text.error();
  EXPECT_EQ(*text, "domain: 3\n");
}

TEST_F(BoundedFileTest, RefusesDevZeroWithoutReadingIt) {
  const auto text = ReadBoundedFile("/dev/zero", "calibration file", kMaxTextFileBytes);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(text.error().message.find("not a regular file"), std::string::npos) << text.error();
  EXPECT_NE(text.error().message.find("/dev/zero"), std::string::npos);
}

TEST_F(BoundedFileTest, RefusesAFifoWithoutWaitingForAWriter) {
  const auto path = (dir_ / "fifo").string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  const auto text = ReadBoundedFile(path, "calibration file", kMaxTextFileBytes);
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.error().message.find("not a regular file"), std::string::npos);
}

TEST_F(BoundedFileTest, RefusesADirectory) {
  const auto text = ReadBoundedFile(dir_.string(), "configuration file", kMaxTextFileBytes);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, ErrorCode::kInvalidArgument);
}

TEST_F(BoundedFileTest, RefusesAFileOverTheLimitByItsSize) {
  // A sparse 1 GB file: reading it would cost a gigabyte; refusing it costs nothing.
  const auto path = (dir_ / "huge.pbtxt").string();
  { std::ofstream(path) << "x"; }
  fs::resize_file(path, 1ull << 30);
  const double before = PeakRssMb();
  const auto text = ReadBoundedFile(path, "calibration file", kMaxTextFileBytes);
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.error().message.find("1073741824 bytes"), std::string::npos) << text.error();
  EXPECT_NE(text.error().message.find("4 MB"), std::string::npos) << text.error();
  EXPECT_LT(PeakRssMb() - before, 10.0);
}

TEST_F(BoundedFileTest, MissingFileSaysSo) {
  const auto text = ReadBoundedFile((dir_ / "nope").string(), "calibration file", 100);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, ErrorCode::kNotFound);
  EXPECT_NE(text.error().message.find("no such file"), std::string::npos) << text.error();
}

// The header reader agrees with OpenCV's encoders on every format it knows.
TEST_F(BoundedFileTest, HeaderSizeMatchesTheEncodedImageInEveryFormat) {
  const cv::Mat image(37, 53, CV_8U, cv::Scalar(90));
  for (const std::string ext : {".png", ".jpg", ".pgm", ".bmp", ".tif"}) {
    std::vector<uchar> bytes;
    ASSERT_TRUE(cv::imencode(ext, image, bytes)) << ext;
    const auto header = ReadImageHeader(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    ASSERT_TRUE(header.ok()) << ext << ": " << header.error();
    EXPECT_EQ(header->width_px, 53u) << ext;
    EXPECT_EQ(header->height_px, 37u) << ext;
    const auto path = Write("image" + ext, std::string(bytes.begin(), bytes.end()));
    const auto read = ReadGreyImageFile(path);
    ASSERT_TRUE(read.ok()) << ext << ": " << read.error();
    EXPECT_EQ(read->cols, 53);
    EXPECT_EQ(read->rows, 37);
  }
}

// A raw frame (8-bit binary PGM) is read into one buffer and returned as a view of its
// pixels there; every other file is decoded into an image of its own. Either way the pixels
// are OpenCV's, and a PGM cut short is refused, not returned with what lay beyond it.
TEST_F(BoundedFileTest, ARawFrameIsAViewOfTheFileBufferWithTheSamePixels) {
  cv::Mat image(61, 83, CV_8U);
  cv::RNG(5).fill(image, cv::RNG::UNIFORM, 0, 256);
  for (const std::string ext : {".pgm", ".png"}) {
    std::vector<uchar> bytes;
    ASSERT_TRUE(cv::imencode(ext, image, bytes)) << ext;
    const auto read =
        ReadGreyImageFile(Write("frame" + ext, std::string(bytes.begin(), bytes.end())));
    ASSERT_TRUE(read.ok()) << ext << ": " << read.error();
    EXPECT_EQ(cv::norm(*read, image, cv::NORM_INF), 0) << ext;
    EXPECT_TRUE(read->isContinuous()) << ext;
    // The PGM's pixels start after its header inside the buffer the file was read into.
    EXPECT_EQ(read->data != read->datastart, ext == ".pgm") << ext;
    if (ext != ".pgm") continue;
    const auto cut =
        ReadGreyImageFile(Write("cut.pgm", std::string(bytes.begin(), bytes.end() - 1)));
    ASSERT_FALSE(cut.ok());
    EXPECT_NE(cut.error().message.find("cut short"), std::string::npos) << cut.error();
  }
  // 16-bit and ASCII PGMs are converted: a copy, by their high byte and their numbers.
  cv::Mat wide;
  image.convertTo(wide, CV_16U, 257);
  for (const auto& [name, params, source] :
       {std::tuple{"wide.pgm", std::vector<int>{}, wide},
        std::tuple{"ascii.pgm", std::vector<int>{cv::IMWRITE_PXM_BINARY, 0}, image}}) {
    std::vector<uchar> bytes;
    ASSERT_TRUE(cv::imencode(".pgm", source, bytes, params)) << name;
    const auto read = ReadGreyImageFile(Write(name, std::string(bytes.begin(), bytes.end())));
    ASSERT_TRUE(read.ok()) << name << ": " << read.error();
    EXPECT_EQ(read->data, read->datastart) << name;
    EXPECT_EQ(cv::norm(*read, image, cv::NORM_INF), 0) << name;
  }
}

// A PNG whose header claims 20000 x 20000 pixels (400 MB decoded) in a few hundred bytes: the
// header is made by OpenCV for a small image, then its size fields and CRC are rewritten.
std::string PngClaiming(uint32_t width, uint32_t height) {
  std::vector<uchar> bytes;
  cv::imencode(".png", cv::Mat(8, 8, CV_8U, cv::Scalar(0)), bytes);
  auto put = [&](size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<uchar>(v >> (24 - 8 * i));
  };
  put(16, width);
  put(20, height);
  // CRC-32 of the IHDR chunk's type and data (bytes 12..28), as PNG requires.
  uint32_t crc = 0xFFFFFFFFu;
  for (size_t i = 12; i < 29; ++i) {
    crc ^= bytes[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  put(29, crc ^ 0xFFFFFFFFu);
  return std::string(bytes.begin(), bytes.end());
}

TEST_F(BoundedFileTest, RefusesAHugeImageByItsHeaderBeforeDecoding) {
  const auto path = Write("huge.png", PngClaiming(20000, 20000));
  const double before = PeakRssMb();
  const auto image = ReadGreyImageFile(path);
  ASSERT_FALSE(image.ok());
  EXPECT_EQ(image.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(image.error().message.find("20000 x 20000"), std::string::npos) << image.error();
  EXPECT_NE(image.error().message.find("64 megapixels"), std::string::npos) << image.error();
  EXPECT_LT(PeakRssMb() - before, 10.0);
}

TEST_F(BoundedFileTest, HugeJpegRefusedToo) {
  std::vector<uchar> bytes;
  cv::imencode(".jpg", cv::Mat(16, 16, CV_8U, cv::Scalar(0)), bytes);
  // Rewrite the frame header's height and width (SOF0: FF C0, length, precision, H, W).
  for (size_t i = 2; i + 9 < bytes.size(); ++i) {
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xC0) {
      bytes[i + 5] = bytes[i + 7] = 0xEA;  // 60000
      bytes[i + 6] = bytes[i + 8] = 0x60;
      break;
    }
  }
  const auto image = ReadGreyImageFile(Write("huge.jpg", std::string(bytes.begin(), bytes.end())));
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.error().message.find("60000 x 60000"), std::string::npos) << image.error();
}

TEST_F(BoundedFileTest, TruncatedAndForeignFilesGetAClearError) {
  std::vector<uchar> bytes;
  cv::imencode(".png", cv::Mat(64, 64, CV_8U, cv::Scalar(7)), bytes);
  const auto cut =
      ReadGreyImageFile(Write("cut.png", std::string(bytes.begin(), bytes.begin() + 60)));
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().message.find("broken or cut short"), std::string::npos) << cut.error();
  const auto text = ReadGreyImageFile(Write("notes.png", "hello, not an image"));
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.error().message.find("not an image format"), std::string::npos) << text.error();
  const auto tiny = ReadGreyImageFile(Write("tiny.png", "\x89PNG\r\n\x1a\n"));
  ASSERT_FALSE(tiny.ok());
}

}  // namespace
}  // namespace monocle
