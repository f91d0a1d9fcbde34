#include "service/io/image_file.h"

#include <algorithm>
#include <fstream>

#include "service/io/bounded_file.h"
#include "service/io/image_codec.h"

namespace monocle {
namespace {

Error BadHeader(const std::string& format, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, "its " + format + " header " + why);
}

uint32_t BigEndian(std::string_view b, size_t at, int bytes) {
  uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
  return v;
}

uint32_t LittleEndian(std::string_view b, size_t at, int bytes) {
  uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
  return v;
}

Result<ImageHeader> Png(std::string_view b) {
  // Signature (8), then the first chunk must be IHDR: length (4), type (4), width, height.
  if (b.size() < 24 || b.substr(12, 4) != "IHDR") return BadHeader("PNG", "has no IHDR chunk");
  return ImageHeader{"PNG", BigEndian(b, 16, 4), BigEndian(b, 20, 4)};
}

Result<ImageHeader> Jpeg(std::string_view b) {
  // Segments after SOI until a start-of-frame marker, which holds the size.
  size_t at = 2;
  while (at + 4 <= b.size()) {
    if (static_cast<uint8_t>(b[at]) != 0xFF) return BadHeader("JPEG", "has a broken segment");
    const uint8_t marker = static_cast<uint8_t>(b[at + 1]);
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
      at += 2;
      continue;
    }
    const uint32_t length = BigEndian(b, at + 2, 2);
    if (length < 2) return BadHeader("JPEG", "has a segment shorter than its length field");
    const bool start_of_frame =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (start_of_frame) {
      if (at + 9 > b.size()) break;
      return ImageHeader{"JPEG", BigEndian(b, at + 7, 2), BigEndian(b, at + 5, 2)};
    }
    if (marker == 0xD9 || marker == 0xDA) break;  // end, or scan data before any frame header
    at += 2 + length;
  }
  return BadHeader("JPEG", "has no frame header (SOF)");
}

Result<ImageHeader> Pnm(std::string_view b) {
  // "P5", then width and height as decimal numbers separated by white space and # comments.
  size_t at = 2;
  const auto width = ReadPnmNumber(b, &at), height = ReadPnmNumber(b, &at);
  if (!width || !height) return BadHeader("PNM", "has no width and height");
  return ImageHeader{"PNM", *width, *height};
}

Result<ImageHeader> Bmp(std::string_view b) {
  if (b.size() < 26) return BadHeader("BMP", "is cut short");
  const uint32_t info_size = LittleEndian(b, 14, 4);
  if (info_size == 12) return ImageHeader{"BMP", LittleEndian(b, 18, 2), LittleEndian(b, 20, 2)};
  const auto width = static_cast<int32_t>(LittleEndian(b, 18, 4));
  const auto height = static_cast<int32_t>(LittleEndian(b, 22, 4));  // negative: top-down
  if (width <= 0 || height == INT32_MIN) return BadHeader("BMP", "has an impossible size");
  return ImageHeader{"BMP", static_cast<uint64_t>(width),
                     static_cast<uint64_t>(height < 0 ? -static_cast<int64_t>(height) : height)};
}

Result<ImageHeader> Tiff(std::string_view b) {
  // The first image file directory: 12-byte entries, tags 256 (width) and 257 (height).
  const bool little = b[0] == 'I';
  auto read = [&](size_t at, int bytes) {
    return little ? LittleEndian(b, at, bytes) : BigEndian(b, at, bytes);
  };
  const uint64_t ifd = read(4, 4);
  if (ifd + 2 > b.size()) return BadHeader("TIFF", "points past the end of the file");
  const uint32_t entries = read(ifd, 2);
  uint64_t size[2] = {0, 0};
  for (uint32_t i = 0; i < entries; ++i) {
    const uint64_t e = ifd + 2 + 12ull * i;
    if (e + 12 > b.size()) return BadHeader("TIFF", "points past the end of the file");
    const uint32_t tag = read(e, 2), type = read(e + 2, 2);
    if (tag != 256 && tag != 257) continue;
    // The first of repeated tags counts, as libtiff reads them (found by image_fuzz).
    if (size[tag - 256] == 0) size[tag - 256] = type == 3 ? read(e + 8, 2) : read(e + 8, 4);
  }
  if (size[0] == 0 || size[1] == 0) return BadHeader("TIFF", "has no width and height");
  return ImageHeader{"TIFF", size[0], size[1]};
}

}  // namespace

std::optional<uint64_t> ReadPnmNumber(std::string_view b, size_t* at) {
  while (*at < b.size() && (std::isspace(static_cast<unsigned char>(b[*at])) || b[*at] == '#')) {
    if (b[*at] == '#') {
      while (*at < b.size() && b[*at] != '\n') ++*at;
    } else {
      ++*at;
    }
  }
  uint64_t value = 0;
  int digits = 0;
  while (*at < b.size() && std::isdigit(static_cast<unsigned char>(b[*at])) && digits < 12) {
    value = value * 10 + static_cast<uint64_t>(b[(*at)++] - '0');
    ++digits;
  }
  if (digits == 0 || digits == 12) return std::nullopt;
  return value;
}

bool HasImageSignature(std::string_view b) {
  return (b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) ||
         (b.size() >= 3 && static_cast<uint8_t>(b[0]) == 0xFF &&
          static_cast<uint8_t>(b[1]) == 0xD8) ||
         (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') ||
         (b.size() >= 2 && b.substr(0, 2) == "BM") ||
         (b.size() >= 8 && (b.substr(0, 4) == std::string_view("II*\0", 4) ||
                            b.substr(0, 4) == std::string_view("MM\0*", 4)));
}

bool LooksLikeImageFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char first[8] = {};
  in.read(first, sizeof first);
  return HasImageSignature(std::string_view(first, static_cast<size_t>(in.gcount())));
}

Result<ImageHeader> ReadImageHeader(std::string_view b) {
  if (b.size() >= 8 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return Png(b);
  if (b.size() >= 3 && static_cast<uint8_t>(b[0]) == 0xFF && static_cast<uint8_t>(b[1]) == 0xD8)
    return Jpeg(b);
  if (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') return Pnm(b);
  if (b.size() >= 2 && b.substr(0, 2) == "BM") return Bmp(b);
  if (b.size() >= 8 && (b.substr(0, 4) == std::string_view("II*\0", 4) ||
                        b.substr(0, 4) == std::string_view("MM\0*", 4)))
    return Tiff(b);
  return MakeError(ErrorCode::kInvalidArgument,
                   "it is not an image format monocle reads (PNG, JPEG, PGM/PNM, BMP, TIFF)");
}

Result<cv::Mat> ReadGreyImageFile(const std::string& path) {
  // Read into a Mat, which a raw frame's pixels are then a view of (DecodeGreyImage).
  cv::Mat file;
  const auto size = ReadBoundedFileInto(path, "image", kMaxImageFileBytes, [&](size_t bytes) {
    file.create(1, static_cast<int>(std::max<size_t>(bytes, 1)), CV_8UC1);
    return reinterpret_cast<char*>(file.data);
  });
  if (!size) return size.error();
  file = file.colRange(0, static_cast<int>(*size));
  const std::string_view bytes(reinterpret_cast<const char*>(file.data), *size);
  const auto header = ReadImageHeader(bytes);
  if (!header) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot read image '" + path + "': " + header.error().message);
  }
  const uint64_t pixels = header->width_px * header->height_px;
  if (header->width_px == 0 || header->height_px == 0 || header->width_px > (1u << 20) ||
      header->height_px > (1u << 20) || pixels > kMaxImagePixels) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot read image '" + path + "': its " + header->format + " header says " +
                         std::to_string(header->width_px) + " x " +
                         std::to_string(header->height_px) +
                         " pixels; monocle reads images of 1 to " +
                         std::to_string(kMaxImagePixels >> 20) + " megapixels");
  }
  auto decoded = DecodeGreyImage(file, header->format);
  if (!decoded) {
    return MakeError(decoded.error().code,
                     "cannot read image '" + path + "': " + decoded.error().message);
  }
  cv::Mat image = std::move(*decoded);
  // The header's size is what the limit was checked against: a file whose data decodes to
  // another size is refused (a header this reader misread must not let a larger image by).
  if (static_cast<uint64_t>(image.cols) != header->width_px ||
      static_cast<uint64_t>(image.rows) != header->height_px) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot read image '" + path + "': its " + header->format + " header says " +
                         std::to_string(header->width_px) + " x " +
                         std::to_string(header->height_px) + " pixels but its data decodes to " +
                         std::to_string(image.cols) + " x " + std::to_string(image.rows));
  }
  return image;
}

}  // namespace monocle
