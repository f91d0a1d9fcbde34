// Loading an image file named by a user: its width and height are read from the format's
// header (PNG, JPEG, PNM, BMP, TIFF) and checked before anything is decoded, so a
// 20000 × 20000 PNG of a few kilobytes costs an error message, not 400 MB. OpenCV 4.6 has no
// public header-only read, and its own pixel limit (OPENCV_IO_MAX_IMAGE_PIXELS, 1 gigapixel)
// is fixed when the library loads, so the header is read here.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "service/common/result.h"

namespace monocle {

// 64 megapixels: above any machine-vision sensor monocle is meant for (and 64 MB decoded).
inline constexpr uint64_t kMaxImagePixels = 64ull << 20;

struct ImageHeader {
  std::string format;  // "PNG", "JPEG", "PNM", "BMP", "TIFF"
  uint64_t width_px = 0, height_px = 0;
};

// Whether a file starting with these bytes (its first 8 are enough) is in a format monocle
// reads: the signature only, as a folder of frames is listed.
bool HasImageSignature(std::string_view first_bytes);

// Whether the file at `path` starts as an image monocle reads does (HasImageSignature).
bool LooksLikeImageFile(const std::string& path);

// The next decimal number of a PNM header from `*at` (after white space and # comments, at
// most 11 digits), moving `*at` past it; nullopt if there is none. The header check and the
// decoder both read PNM sizes with it, so they cannot disagree.
std::optional<uint64_t> ReadPnmNumber(std::string_view bytes, size_t* at);

// The image's size from its first bytes. kInvalidArgument for an unknown format or a header
// that does not hold together.
Result<ImageHeader> ReadImageHeader(std::string_view bytes);

// The file as an 8-bit grey image: regular file, ≤ kMaxImageFileBytes, ≤ kMaxImagePixels by
// its header, then decoded. Errors name the file and say what to do.
Result<cv::Mat> ReadGreyImageFile(const std::string& path);

}  // namespace monocle
