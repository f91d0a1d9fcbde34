// CRC-32 (ISO-HDLC, the one MCAP's chunks and summary use) over any length, by zlib; for
// mcap_writer.cc and mcap_reader.cc only.
#pragma once

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <string_view>

namespace monocle::mcap {

inline uint32_t Crc32(std::string_view bytes, uint32_t crc = 0) {
  // zlib takes uInt lengths: feed it a gigabyte at a time.
  while (!bytes.empty()) {
    const size_t n = std::min<size_t>(bytes.size(), 1u << 30);
    crc = static_cast<uint32_t>(
        crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(n)));
    bytes.remove_prefix(n);
  }
  return crc;
}

}  // namespace monocle::mcap
