// Fuzz target: loading an image file named on the command line (`monocle floor calibrate
// IMG`, `monocle corner locate IMG`, a file camera's frames). The bytes are a real file (a
// memfd, so no disk is worn): the header check must refuse anything over the pixel limit
// before OpenCV decodes it, and whatever decodes must be as large as the header said.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "service/io/image_file.h"

#include "tests/fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const auto header = monocle::ReadImageHeader(bytes);

  const int fd = memfd_create("image_fuzz", 0);
  if (fd < 0) return 0;
  if (write(fd, data, size) != static_cast<ssize_t>(size)) {
    close(fd);
    return 0;
  }
  const auto image = monocle::ReadGreyImageFile("/proc/self/fd/" + std::to_string(fd));
  close(fd);
  if (!image) {
    FUZZ_CHECK(!image.error().message.empty());
    return 0;
  }
  // Decoded only when the header was read and within the limit, and to the header's size.
  FUZZ_CHECK(header.ok());
  FUZZ_CHECK(header->width_px > 0 && header->height_px > 0);
  FUZZ_CHECK(header->width_px * header->height_px <= monocle::kMaxImagePixels);
  FUZZ_CHECK(static_cast<uint64_t>(image->cols) == header->width_px &&
             static_cast<uint64_t>(image->rows) == header->height_px);
  return 0;
}
