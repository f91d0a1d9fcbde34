// Image files decoded and encoded with libpng, libjpeg(-turbo) and libtiff directly, PNM and
// BMP by hand. OpenCV's imgcodecs would do all of it, but it links GDAL, HDF5, poppler and
// some hundred further libraries, and loading them was 50 of the 60 ms every `monocle`
// command took to start (bench/README.md); the runtime image carried them all.
//
// Decoding gives what cv::imdecode(bytes, cv::IMREAD_GRAYSCALE) gives for the same file (the
// tests compare them pixel for pixel): colour through the same weights, 16-bit samples by
// their high byte. The caller checks the size first (image_file.h); these functions trust
// nothing else in the bytes.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "service/common/result.h"

namespace monocle {

// The image in `bytes` (a format ReadImageHeader named: "PNG", "JPEG", "PNM", "BMP", "TIFF")
// as 8-bit grey. kInvalidArgument, saying what is wrong, for data that is broken, cut short
// or of a kind not read here (compressed BMP, PNM bitmaps).
Result<cv::Mat> DecodeGreyImage(std::string_view bytes, const std::string& format);

// The same, from a whole file held in `file` (one row of CV_8U): an 8-bit binary PGM (the
// format of raw frames) comes back as a view of its pixels in `file`, sharing it, not a
// copy: copying a 1280 x 1024 frame was 3 % of `monocle corner locate`'s time per frame.
Result<cv::Mat> DecodeGreyImage(const cv::Mat& file, const std::string& format);

// An 8-bit grey or BGR image as a file's bytes, by the file name's extension: .png, .jpg or
// .jpeg (quality 0-100), .pgm / .ppm / .pnm (binary, grey or colour as the image is).
Result<std::vector<uint8_t>> EncodeImage(const cv::Mat& image, const std::string& extension,
                                         int jpeg_quality = 95);

// Whether EncodeImage writes files of this extension (".png", ".JPG", ...).
bool CanWriteImageExtension(const std::string& extension);

// EncodeImage by `path`'s extension, written to `path`.
Status WriteImageFile(const std::string& path, const cv::Mat& image);

}  // namespace monocle
