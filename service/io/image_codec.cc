#include "service/io/image_codec.h"

#include <jpeglib.h>
#include <png.h>
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "service/io/image_file.h"

namespace monocle {
namespace {

Error Broken(const std::string& format, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, "its " + format + " data " + why);
}

// Whether a decoder may allocate an image of this size. The caller has checked the header
// (image_file.h), but a decoder reads the size again, its own way: one that disagrees is
// still refused here before it costs memory (ReadGreyImageFile then refuses the mismatch).
bool SizeAllowed(uint64_t width, uint64_t height) {
  return width > 0 && height > 0 && width <= (1u << 20) && height <= (1u << 20) &&
         width * height <= kMaxImagePixels;
}
Error TooLarge(const std::string& format, uint64_t width, uint64_t height) {
  return Broken(format, "says " + std::to_string(width) + " x " + std::to_string(height) +
                            " pixels; monocle reads images of 1 to " +
                            std::to_string(kMaxImagePixels >> 20) + " megapixels");
}

// Colour to grey as OpenCV's image readers do it (not cv::cvtColor, whose rounding differs by
// one grey level now and then): BT.601 weights in 14-bit fixed point, rounded.
int GreyOf(int r, int g, int b) { return (r * 4899 + g * 9617 + b * 1868 + (1 << 13)) >> 14; }

// `rgb_order`: red first (else blue first) among each pixel's first three channels.
cv::Mat GreyFromColour(const cv::Mat& colour, bool rgb_order) {
  cv::Mat grey(colour.rows, colour.cols, CV_8UC1);
  const int channels = colour.channels();
  for (int y = 0; y < colour.rows; ++y) {
    const uint8_t* in = colour.ptr<uint8_t>(y);
    uint8_t* out = grey.ptr<uint8_t>(y);
    for (int x = 0; x < colour.cols; ++x, in += channels)
      out[x] = static_cast<uint8_t>(rgb_order ? GreyOf(in[0], in[1], in[2])
                                              : GreyOf(in[2], in[1], in[0]));
  }
  return grey;
}

// --- PNM (P2, P3, P5, P6), as OpenCV reads it: samples of a maxval above 255 by their high
// byte, colour to grey with the BT.601 weights. ---

// `file`: the 1-row CV_8U Mat `b` lies in, if any; an 8-bit binary PGM is then a view of it.
Result<cv::Mat> DecodePnm(std::string_view b, const cv::Mat* file = nullptr) {
  const char kind = b.size() >= 2 ? b[1] : '0';
  if (kind != '2' && kind != '3' && kind != '5' && kind != '6')
    return Broken("PNM", "is a kind monocle does not read (P" + std::string(1, kind) +
                             "; grey P2/P5 and colour P3/P6 are read)");
  size_t at = 2;
  const auto width = ReadPnmNumber(b, &at), height = ReadPnmNumber(b, &at),
             maxval = ReadPnmNumber(b, &at);
  if (!width || !height || !maxval || *maxval == 0 || *maxval > 65535)
    return Broken("PNM", "has a broken header (width, height, maxval)");
  if (!SizeAllowed(*width, *height)) return TooLarge("PNM", *width, *height);
  const int channels = kind == '3' || kind == '6' ? 3 : 1;
  const int sample_bytes = *maxval > 255 ? 2 : 1;
  const size_t samples = static_cast<size_t>(*width) * *height * channels;
  if (kind == '5' && sample_bytes == 1 && file != nullptr) {
    ++at;  // the single white-space byte after maxval
    if (at > b.size() || b.size() - at < samples) return Broken("PNM", "is broken or cut short");
    const auto offset =
        static_cast<int>(reinterpret_cast<const uchar*>(b.data()) + at - file->data);
    return cv::Mat(*file, cv::Range::all(), cv::Range(offset, offset + static_cast<int>(samples)))
        .reshape(1, static_cast<int>(*height));
  }
  cv::Mat decoded(static_cast<int>(*height), static_cast<int>(*width), CV_8UC(channels));
  uint8_t* out = decoded.ptr<uint8_t>();  // continuous: just allocated
  if (kind == '5' || kind == '6') {
    ++at;  // the single white-space byte after maxval
    if (at > b.size() || (b.size() - at) / sample_bytes < samples)
      return Broken("PNM", "is broken or cut short");
    const auto* in = reinterpret_cast<const uint8_t*>(b.data() + at);
    if (sample_bytes == 1) {
      std::memcpy(out, in, samples);
    } else {
      for (size_t i = 0; i < samples; ++i) out[i] = in[2 * i];  // big-endian: the high byte
    }
  } else {
    for (size_t i = 0; i < samples; ++i) {
      const auto v = ReadPnmNumber(b, &at);
      if (!v) return Broken("PNM", "is broken or cut short (something other than numbers)");
      out[i] = static_cast<uint8_t>(sample_bytes == 2 ? std::min<uint64_t>(*v, 65535) >> 8
                                                      : std::min<uint64_t>(*v, 255));
    }
  }
  if (channels == 1) return decoded;
  return GreyFromColour(decoded, /*rgb_order=*/true);
}

// --- PNG through libpng, with the transformations OpenCV asks for. ---

struct PngSource {
  std::string_view bytes;
  size_t at = 0;
};

void ReadPngBytes(png_structp png, png_bytep out, png_size_t n) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (n > source->bytes.size() - source->at) png_error(png, "cut short");
  std::memcpy(out, source->bytes.data() + source->at, n);
  source->at += n;
}

void PngErrorToJump(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text != nullptr) *text = message;
  png_longjmp(png, 1);
}
void PngWarningIgnored(png_structp, png_const_charp) {}

// One libpng read, all of its state made before setjmp so a longjmp skips no destructor.
class PngReader {
 public:
  PngReader() {
    png_ =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &message_, PngErrorToJump, PngWarningIgnored);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
  }
  ~PngReader() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  Result<cv::Mat> Read(std::string_view bytes) {
    if (png_ == nullptr || info_ == nullptr)
      return MakeError(ErrorCode::kIo, "libpng could not start (out of memory?)");
    source_.bytes = bytes;
    rows_.clear();
    if (setjmp(png_jmpbuf(png_)) != 0)
      return Broken("PNG", "is broken or cut short (" + message_ + ")");
    png_set_read_fn(png_, &source_, ReadPngBytes);
    png_read_info(png_, info_);
    png_uint_32 width = 0, height = 0;
    int bit_depth = 0, color_type = 0;
    png_get_IHDR(png_, info_, &width, &height, &bit_depth, &color_type, nullptr, nullptr, nullptr);
    if (!SizeAllowed(width, height)) return TooLarge("PNG", width, height);
    if (bit_depth == 16) png_set_strip_16(png_);
    png_set_strip_alpha(png_);
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png_);
    if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8)
      png_set_expand_gray_1_2_4_to_8(png_);
    png_set_rgb_to_gray(png_, 1, 0.299, 0.587);
    png_set_interlace_handling(png_);
    png_read_update_info(png_, info_);
    image_.create(static_cast<int>(height), static_cast<int>(width), CV_8UC1);
    rows_.resize(height);
    for (png_uint_32 y = 0; y < height; ++y) rows_[y] = image_.ptr<uint8_t>(static_cast<int>(y));
    png_read_image(png_, rows_.data());
    png_read_end(png_, nullptr);
    return image_;
  }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  std::string message_;
  PngSource source_;
  std::vector<png_bytep> rows_;
  cv::Mat image_;
};

// --- JPEG through libjpeg(-turbo): errors leave by longjmp with the library's message. ---

struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

void JpegErrorToJump(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, error->message);
  std::longjmp(error->jump, 1);
}
void JpegWarningIgnored(j_common_ptr, int) {}

class JpegReader {
 public:
  JpegReader() {
    info_.err = jpeg_std_error(&error_.manager);
    error_.manager.error_exit = JpegErrorToJump;
    error_.manager.emit_message = JpegWarningIgnored;
    jpeg_create_decompress(&info_);
  }
  ~JpegReader() { jpeg_destroy_decompress(&info_); }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  Result<cv::Mat> Read(std::string_view bytes) {
    if (setjmp(error_.jump) != 0)
      return Broken("JPEG", std::string("is broken or cut short (") + error_.message + ")");
    jpeg_mem_src(&info_, reinterpret_cast<const unsigned char*>(bytes.data()),
                 static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&info_, TRUE);
    if (!SizeAllowed(info_.image_width, info_.image_height))
      return TooLarge("JPEG", info_.image_width, info_.image_height);
    // As OpenCV: grey straight from the decoder (its Y), CMYK converted after.
    const bool cmyk = info_.num_components == 4;
    info_.out_color_space = cmyk ? JCS_CMYK : JCS_GRAYSCALE;
    jpeg_start_decompress(&info_);
    image_.create(static_cast<int>(info_.output_height), static_cast<int>(info_.output_width),
                  CV_8UC(cmyk ? 4 : 1));
    while (info_.output_scanline < info_.output_height) {
      JSAMPROW row = image_.ptr<uint8_t>(static_cast<int>(info_.output_scanline));
      jpeg_read_scanlines(&info_, &row, 1);
    }
    jpeg_finish_decompress(&info_);
    if (!cmyk) return image_;
    // Adobe's inverted CMYK, as OpenCV converts it (image_codec_test): red from C, green
    // from M, blue from Y, each k - (255 - v) k / 256, then the BT.601 weights.
    cv::Mat grey(image_.rows, image_.cols, CV_8UC1);
    for (int y = 0; y < image_.rows; ++y) {
      const uint8_t* in = image_.ptr<uint8_t>(y);
      uint8_t* out = grey.ptr<uint8_t>(y);
      for (int x = 0; x < image_.cols; ++x, in += 4) {
        const int k = in[3];
        const int r = k - (((255 - in[0]) * k) >> 8), g = k - (((255 - in[1]) * k) >> 8),
                  b = k - (((255 - in[2]) * k) >> 8);
        out[x] = static_cast<uint8_t>(GreyOf(r, g, b));
      }
    }
    return grey;
  }

 private:
  jpeg_decompress_struct info_{};
  JpegError error_;
  cv::Mat image_;
};

// --- BMP by hand: uncompressed 1, 4, 8 (palette), 24 and 32 bit. ---

uint32_t Le(std::string_view b, size_t at, int bytes) {
  uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
  return v;
}

Result<cv::Mat> DecodeBmp(std::string_view b) {
  if (b.size() < 54) return Broken("BMP", "is broken or cut short");
  const uint32_t data_at = Le(b, 10, 4), info_size = Le(b, 14, 4);
  if (info_size < 40) return Broken("BMP", "has an old OS/2 header monocle does not read");
  const auto width = static_cast<int32_t>(Le(b, 18, 4));
  const auto height_signed = static_cast<int32_t>(Le(b, 22, 4));
  const uint32_t bits = Le(b, 28, 2), compression = Le(b, 30, 4);
  if (width <= 0 || height_signed == 0 || height_signed == INT32_MIN)
    return Broken("BMP", "has an impossible size");
  if (compression != 0 && !(compression == 3 && bits == 32))
    return Broken("BMP",
                  "is compressed (RLE or bit fields), which monocle does not read; "
                  "save it as PNG");
  if (bits != 1 && bits != 4 && bits != 8 && bits != 24 && bits != 32)
    return Broken("BMP", "has " + std::to_string(bits) +
                             " bits a pixel; monocle reads 1, 4, 8, "
                             "24 and 32");
  const int height = height_signed < 0 ? -height_signed : height_signed;
  if (!SizeAllowed(static_cast<uint64_t>(width), static_cast<uint64_t>(height)))
    return TooLarge("BMP", static_cast<uint64_t>(width), static_cast<uint64_t>(height));
  const uint64_t row_bytes = ((static_cast<uint64_t>(width) * bits + 31) / 32) * 4;
  if (data_at > b.size() || (b.size() - data_at) / row_bytes < static_cast<uint64_t>(height))
    return Broken("BMP", "is broken or cut short");
  // Palette entries (B, G, R, 0) after the info header; grey through the BT.601 weights.
  std::array<uint8_t, 256> palette_grey{};
  if (bits <= 8) {
    uint32_t colours = Le(b, 46, 4);
    if (colours == 0 || colours > (1u << bits)) colours = 1u << bits;
    const size_t palette_at = 14 + static_cast<size_t>(info_size);
    if (palette_at + 4 * colours > data_at) return Broken("BMP", "has a broken palette");
    for (uint32_t i = 0; i < colours; ++i) {
      const auto* p = reinterpret_cast<const uint8_t*>(b.data() + palette_at + 4 * i);
      palette_grey[i] = static_cast<uint8_t>(GreyOf(p[2], p[1], p[0]));
    }
  }
  cv::Mat bgr(height, width, bits >= 24 ? CV_8UC(bits / 8) : CV_8UC1);
  for (int y = 0; y < height; ++y) {
    const int stored = height_signed < 0 ? y : height - 1 - y;  // bottom-up unless negative
    const auto* in = reinterpret_cast<const uint8_t*>(b.data() + data_at +
                                                      static_cast<size_t>(stored) * row_bytes);
    uint8_t* out = bgr.ptr<uint8_t>(y);
    if (bits >= 24) {
      std::memcpy(out, in, static_cast<size_t>(width) * (bits / 8));
      continue;
    }
    for (int x = 0; x < width; ++x) {
      const int bit = x * static_cast<int>(bits);
      const int index = (in[bit / 8] >> (8 - static_cast<int>(bits) - bit % 8)) & ((1 << bits) - 1);
      out[x] = palette_grey[index];
    }
  }
  if (bits <= 8) return bgr;
  return GreyFromColour(bgr, /*rgb_order=*/false);
}

// --- TIFF through libtiff, read from memory, every kind through its RGBA reader. ---

struct TiffSource {
  std::string_view bytes;
  toff_t at = 0;
};
tmsize_t TiffRead(thandle_t h, void* out, tmsize_t n) {
  auto* s = static_cast<TiffSource*>(h);
  if (n < 0 || s->at > s->bytes.size()) return 0;
  const auto available = static_cast<tmsize_t>(s->bytes.size() - s->at);
  const tmsize_t taken = std::min(n, available);
  std::memcpy(out, s->bytes.data() + s->at, static_cast<size_t>(taken));
  s->at += static_cast<toff_t>(taken);
  return taken;
}
tmsize_t TiffWrite(thandle_t, void*, tmsize_t) { return 0; }
toff_t TiffSeek(thandle_t h, toff_t offset, int whence) {
  auto* s = static_cast<TiffSource*>(h);
  const toff_t base = whence == SEEK_CUR ? s->at : whence == SEEK_END ? s->bytes.size() : 0;
  s->at = base + offset;
  return s->at;
}
int TiffClose(thandle_t) { return 0; }
toff_t TiffSize(thandle_t h) { return static_cast<TiffSource*>(h)->bytes.size(); }

Result<cv::Mat> DecodeTiff(std::string_view b) {
  static std::once_flag quiet;  // libtiff prints to stderr by default; its failures come back
  std::call_once(quiet, [] {
    TIFFSetErrorHandler(nullptr);
    TIFFSetWarningHandler(nullptr);
  });
  TiffSource source{b};
  TIFF* tiff = TIFFClientOpen("image", "rm", &source, TiffRead, TiffWrite, TiffSeek, TiffClose,
                              TiffSize, nullptr, nullptr);
  if (tiff == nullptr) return Broken("TIFF", "is broken or cut short (libtiff cannot open it)");
  uint32_t width = 0, height = 0;
  TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &height);
  if (!SizeAllowed(width, height)) {
    TIFFClose(tiff);
    return TooLarge("TIFF", width, height);
  }
  cv::Mat rgba(static_cast<int>(height), static_cast<int>(width), CV_8UC4);
  const int ok =
      TIFFReadRGBAImageOriented(tiff, width, height, rgba.ptr<uint32_t>(), ORIENTATION_TOPLEFT, 0);
  TIFFClose(tiff);
  if (!ok) return Broken("TIFF", "is broken, cut short or of a kind libtiff cannot read");
  // Each pixel is A B G R from the high byte down: in memory (little-endian) R, G, B, A.
  return GreyFromColour(rgba, /*rgb_order=*/true);
}

// --- Encoders. ---

void WritePngBytes(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}
void FlushNothing(png_structp) {}

class PngWriter {
 public:
  PngWriter() {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message_, PngErrorToJump,
                                   PngWarningIgnored);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
  }
  ~PngWriter() { png_destroy_write_struct(&png_, &info_); }
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  Result<std::vector<uint8_t>> Write(const cv::Mat& image) {
    if (png_ == nullptr || info_ == nullptr)
      return MakeError(ErrorCode::kIo, "libpng could not start (out of memory?)");
    rows_.clear();
    out_.clear();
    if (setjmp(png_jmpbuf(png_)) != 0)
      return MakeError(ErrorCode::kIo, "cannot encode PNG: " + message_);
    png_set_write_fn(png_, &out_, WritePngBytes, FlushNothing);
    // Fast over small: as OpenCV writes PNG by default.
    png_set_compression_level(png_, 1);
    png_set_IHDR(png_, info_, static_cast<png_uint_32>(image.cols),
                 static_cast<png_uint_32>(image.rows), 8,
                 image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png_, info_);
    if (image.channels() == 3) png_set_bgr(png_);
    rows_.resize(static_cast<size_t>(image.rows));
    for (int y = 0; y < image.rows; ++y) rows_[y] = const_cast<png_bytep>(image.ptr<uint8_t>(y));
    png_write_image(png_, rows_.data());
    png_write_end(png_, nullptr);
    return std::move(out_);
  }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  std::string message_;
  std::vector<png_bytep> rows_;
  std::vector<uint8_t> out_;
};

class JpegWriter {
 public:
  JpegWriter() {
    info_.err = jpeg_std_error(&error_.manager);
    error_.manager.error_exit = JpegErrorToJump;
    error_.manager.emit_message = JpegWarningIgnored;
    jpeg_create_compress(&info_);
  }
  ~JpegWriter() {
    jpeg_destroy_compress(&info_);
    std::free(buffer_);
  }
  JpegWriter(const JpegWriter&) = delete;
  JpegWriter& operator=(const JpegWriter&) = delete;

  Result<std::vector<uint8_t>> Write(const cv::Mat& image, int quality) {
    if (setjmp(error_.jump) != 0)
      return MakeError(ErrorCode::kIo, std::string("cannot encode JPEG: ") + error_.message);
    jpeg_mem_dest(&info_, &buffer_, &size_);
    info_.image_width = static_cast<JDIMENSION>(image.cols);
    info_.image_height = static_cast<JDIMENSION>(image.rows);
    info_.input_components = image.channels();
    info_.in_color_space = image.channels() == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
    // OpenCV's settings: the defaults, the quality limited to baseline tables.
    jpeg_set_defaults(&info_);
    jpeg_set_quality(&info_, std::clamp(quality, 0, 100), TRUE);
    jpeg_start_compress(&info_, TRUE);
    while (info_.next_scanline < info_.image_height) {
      JSAMPROW row =
          const_cast<JSAMPROW>(image.ptr<uint8_t>(static_cast<int>(info_.next_scanline)));
      jpeg_write_scanlines(&info_, &row, 1);
    }
    jpeg_finish_compress(&info_);
    return std::vector<uint8_t>(buffer_, buffer_ + size_);
  }

 private:
  jpeg_compress_struct info_{};
  JpegError error_;
  unsigned char* buffer_ = nullptr;
  unsigned long size_ = 0;
};

std::vector<uint8_t> EncodePnm(const cv::Mat& image) {
  const bool colour = image.channels() == 3;
  const std::string header = std::string(colour ? "P6" : "P5") + "\n" + std::to_string(image.cols) +
                             " " + std::to_string(image.rows) + "\n255\n";
  std::vector<uint8_t> out(header.begin(), header.end());
  out.reserve(out.size() + image.total() * image.channels());
  for (int y = 0; y < image.rows; ++y) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    if (!colour) {
      out.insert(out.end(), row, row + image.cols);
      continue;
    }
    for (int x = 0; x < image.cols; ++x, row += 3) {
      out.push_back(row[2]);
      out.push_back(row[1]);
      out.push_back(row[0]);
    }
  }
  return out;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

Result<cv::Mat> DecodeGreyImage(std::string_view bytes, const std::string& format) {
  if (format == "PNM") return DecodePnm(bytes);
  if (format == "PNG") return PngReader().Read(bytes);
  if (format == "JPEG") return JpegReader().Read(bytes);
  if (format == "BMP") return DecodeBmp(bytes);
  if (format == "TIFF") return DecodeTiff(bytes);
  return MakeError(ErrorCode::kInvalidArgument, "it is not an image format monocle reads");
}

Result<cv::Mat> DecodeGreyImage(const cv::Mat& file, const std::string& format) {
  if (file.type() != CV_8UC1 || file.rows != 1)
    return MakeError(ErrorCode::kInvalidArgument, "a file's bytes are one row of CV_8U");
  const std::string_view bytes(reinterpret_cast<const char*>(file.data), file.total());
  if (format == "PNM") return DecodePnm(bytes, &file);
  return DecodeGreyImage(bytes, format);
}

bool CanWriteImageExtension(const std::string& extension) {
  const std::string ext = Lower(extension);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pgm" || ext == ".ppm" ||
         ext == ".pnm";
}

Result<std::vector<uint8_t>> EncodeImage(const cv::Mat& image, const std::string& extension,
                                         int jpeg_quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    return MakeError(ErrorCode::kInvalidArgument, "only 8-bit grey or colour images are written");
  const std::string ext = Lower(extension);
  if (!CanWriteImageExtension(ext))
    return MakeError(ErrorCode::kInvalidArgument,
                     "cannot write a '" + extension + "' image: use .png, .jpg or .pgm");
  if (ext == ".png") return PngWriter().Write(image);
  if (ext == ".jpg" || ext == ".jpeg") return JpegWriter().Write(image, jpeg_quality);
  if (ext == ".pgm" && image.channels() != 1) {
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    return EncodePnm(grey);
  }
  return EncodePnm(image);  // .ppm, .pnm
}

Status WriteImageFile(const std::string& path, const cv::Mat& image) {
  auto bytes = EncodeImage(image, std::filesystem::path(path).extension().string());
  if (!bytes)
    return MakeError(bytes.error().code, "cannot write '" + path + "': " + bytes.error().message);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes->data()),
            static_cast<std::streamsize>(bytes->size()));
  out.close();
  if (!out)
    return MakeError(ErrorCode::kIo, "cannot write '" + path + "' (is its folder writable?)");
  return Ok{};
}

}  // namespace monocle
