// image_codec against OpenCV's imgcodecs, which it replaces in monocle's programs: the same
// grey pixels from the same files (made here by OpenCV in every kind it writes), the same
// JPEG bytes (the realistic renders compress through it), and clear errors for broken data.
#include "service/io/image_codec.h"

#include <gtest/gtest.h>
#include <jpeglib.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

namespace monocle {
namespace {

// A frame with every grey level, fine noise and a soft edge: what cameras and renders give.
cv::Mat Frame(int type, uint64_t seed) {
  cv::Mat image(97, 131, type);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  cv::GaussianBlur(image, image, cv::Size(5, 5), 1.2);
  return image;
}

std::string_view View(const std::vector<uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

std::vector<uint8_t> OpenCvEncode(const std::string& ext, const cv::Mat& image,
                                  const std::vector<int>& params = {}) {
  std::vector<uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes, params)) << ext;
  return bytes;
}

// Decoded here and by cv::imdecode(..., IMREAD_GRAYSCALE): pixel for pixel the same.
void ExpectSameAsOpenCv(const std::vector<uint8_t>& bytes, const std::string& format,
                        const std::string& what) {
  const auto ours = DecodeGreyImage(View(bytes), format);
  ASSERT_TRUE(ours.ok()) << what << ": " << ours.error().message;
  const cv::Mat theirs = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(ours->type(), CV_8UC1) << what;
  ASSERT_EQ(ours->size(), theirs.size()) << what;
  EXPECT_EQ(cv::norm(*ours, theirs, cv::NORM_INF), 0) << what;
}

TEST(ImageCodecTest, DecodesEveryKindOpenCvWritesToTheSamePixels) {
  for (int type : {CV_8UC1, CV_8UC3, CV_16UC1, CV_16UC3, CV_8UC4}) {
    const cv::Mat image = Frame(type, 7 + type);
    const std::string kind = "type " + std::to_string(type);
    ExpectSameAsOpenCv(OpenCvEncode(".png", image), "PNG", "PNG " + kind);
    if (CV_MAT_CN(type) != 4)
      ExpectSameAsOpenCv(OpenCvEncode(".tiff", image), "TIFF", "TIFF " + kind);
    if (CV_MAT_DEPTH(type) == CV_8U) {
      ExpectSameAsOpenCv(OpenCvEncode(".bmp", image), "BMP", "BMP " + kind);
      for (int q : {70, 90})
        ExpectSameAsOpenCv(OpenCvEncode(".jpg", image, {cv::IMWRITE_JPEG_QUALITY, q}), "JPEG",
                           "JPEG q" + std::to_string(q) + " " + kind);
    }
    if (CV_MAT_CN(type) == 1) {
      ExpectSameAsOpenCv(OpenCvEncode(".pgm", image), "PNM", "PGM " + kind);
      ExpectSameAsOpenCv(OpenCvEncode(".pgm", image, {cv::IMWRITE_PXM_BINARY, 0}), "PNM",
                         "ASCII PGM " + kind);
    }
    if (CV_MAT_CN(type) == 3) ExpectSameAsOpenCv(OpenCvEncode(".ppm", image), "PNM", "PPM " + kind);
  }
  // A two-level PNG (1 bit a pixel) and a progressive JPEG.
  cv::Mat two_level = Frame(CV_8UC1, 3) > 128;
  ExpectSameAsOpenCv(OpenCvEncode(".png", two_level, {cv::IMWRITE_PNG_BILEVEL, 1}), "PNG",
                     "1-bit PNG");
  ExpectSameAsOpenCv(OpenCvEncode(".jpg", Frame(CV_8UC1, 5), {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
                     "JPEG", "progressive JPEG");
}

// A CMYK JPEG (as print workflows and some scanners write them; OpenCV writes none): made
// with libjpeg directly (its defaults add the Adobe marker), from random CMYK samples.
std::vector<uint8_t> CmykJpeg(const cv::Mat& cmyk) {
  jpeg_compress_struct info{};
  jpeg_error_mgr error{};
  info.err = jpeg_std_error(&error);
  jpeg_create_compress(&info);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&info, &buffer, &size);
  info.image_width = static_cast<JDIMENSION>(cmyk.cols);
  info.image_height = static_cast<JDIMENSION>(cmyk.rows);
  info.input_components = 4;
  info.in_color_space = JCS_CMYK;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 90, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(cmyk.ptr<uint8_t>(static_cast<int>(info.next_scanline)));
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  std::vector<uint8_t> out(buffer, buffer + size);
  jpeg_destroy_compress(&info);
  std::free(buffer);
  return out;
}

TEST(ImageCodecTest, DecodesCmykJpegAsOpenCvDoes) {
  ExpectSameAsOpenCv(CmykJpeg(Frame(CV_8UC4, 31)), "JPEG", "CMYK JPEG");
}

TEST(ImageCodecTest, CompressesJpegToOpenCvsBytes) {
  // The realistic renders go through JPEG; their figures were measured with OpenCV's encoder.
  for (int q : {70, 80, 90, 95}) {
    const cv::Mat grey = Frame(CV_8UC1, 100 + q);
    const auto ours = EncodeImage(grey, ".jpg", q);
    ASSERT_TRUE(ours.ok());
    EXPECT_EQ(*ours, OpenCvEncode(".jpg", grey, {cv::IMWRITE_JPEG_QUALITY, q})) << "quality " << q;
  }
}

TEST(ImageCodecTest, WritesWhatOpenCvReadsBack) {
  const cv::Mat grey = Frame(CV_8UC1, 11), colour = Frame(CV_8UC3, 12);
  for (const std::string ext : {".png", ".PNG", ".pgm", ".ppm", ".pnm"}) {
    for (const cv::Mat* image : {&grey, &colour}) {
      const auto bytes = EncodeImage(*image, ext);
      ASSERT_TRUE(bytes.ok()) << ext;
      const cv::Mat back = cv::imdecode(*bytes, cv::IMREAD_UNCHANGED);
      const cv::Mat expected = ext == ".pgm" && image->channels() == 3 ? [&] {
        cv::Mat g;
        cv::cvtColor(*image, g, cv::COLOR_BGR2GRAY);
        return g;
      }()
                                                                        : *image;
      ASSERT_EQ(back.type(), expected.type()) << ext;
      EXPECT_EQ(cv::norm(back, expected, cv::NORM_INF), 0) << ext;
    }
  }
  // JPEG in colour (overlays): the bytes OpenCV writes at its default quality.
  const auto jpeg = EncodeImage(colour, ".jpeg");
  ASSERT_TRUE(jpeg.ok());
  EXPECT_EQ(*jpeg, OpenCvEncode(".jpg", colour));
}

TEST(ImageCodecTest, BrokenDataIsAnErrorNamingTheFormat) {
  const cv::Mat grey = Frame(CV_8UC1, 21);
  const std::vector<std::pair<std::string, std::string>> kinds = {
      {".png", "PNG"}, {".jpg", "JPEG"}, {".pgm", "PNM"}, {".bmp", "BMP"}, {".tiff", "TIFF"}};
  for (const auto& [ext, format] : kinds) {
    const auto bytes = OpenCvEncode(ext, grey);
    for (size_t keep : {bytes.size() / 2, size_t{20}}) {
      const auto cut = DecodeGreyImage(View(bytes).substr(0, keep), format);
      // A JPEG cut in its scan decodes with the rest grey, as libjpeg does: not an error.
      if (format == "JPEG" && keep == bytes.size() / 2) continue;
      ASSERT_FALSE(cut.ok()) << format << " cut to " << keep << " bytes";
      EXPECT_NE(cut.error().message.find(format), std::string::npos) << cut.error().message;
    }
  }
  // Kinds not read say so, and what to do.
  std::vector<uint8_t> rle = OpenCvEncode(".bmp", grey);
  rle[30] = 1;  // BI_RLE8
  const auto refused = DecodeGreyImage(View(rle), "BMP");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("PNG"), std::string::npos) << refused.error().message;
  EXPECT_FALSE(DecodeGreyImage("P4\n8 8\n", "PNM").ok());
}

TEST(ImageCodecTest, UnknownOutputExtensionsAreRefusedWithTheOnesThatWork) {
  EXPECT_TRUE(CanWriteImageExtension(".JPG"));
  EXPECT_FALSE(CanWriteImageExtension(".webp"));
  const auto refused = EncodeImage(Frame(CV_8UC1, 1), ".webp");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find(".png"), std::string::npos);
  const auto path = std::filesystem::temp_directory_path() / "image_codec_test_no_dir" / "a.png";
  const auto unwritable = WriteImageFile(path.string(), Frame(CV_8UC1, 1));
  ASSERT_FALSE(unwritable.ok());
  EXPECT_NE(unwritable.error().message.find("a.png"), std::string::npos);
}

}  // namespace
}  // namespace monocle
