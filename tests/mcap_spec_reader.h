// A second, deliberately minimal MCAP reader for tests, written from the specification
// (https://mcap.dev/spec) without any of monocle's MCAP code: it walks every record of the
// data section from the start (descending into chunks, zstd or not) and lists channels and
// message counts, so a test can hold monocle's writer and reader against it.
#pragma once

#include <zstd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>

namespace monocle::testing {

struct SpecReadResult {
  std::map<uint16_t, std::string> topics;        // channel id -> topic
  std::map<uint16_t, std::string> schema_names;  // schema id -> name
  std::map<uint16_t, uint16_t> channel_schema;   // channel id -> schema id
  std::map<std::string, uint64_t> counts;        // topic -> messages
  uint64_t messages = 0;
  uint64_t chunks = 0;
  bool has_footer = false;                // ends in footer + magic
  uint64_t statistics_message_count = 0;  // from the summary's Statistics record, if any
};

namespace spec_detail {
inline uint64_t Le(const std::string& b, size_t at, int bytes) {
  if (at + bytes > b.size()) throw std::runtime_error("read past the end");
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
  return v;
}
inline std::string Str(const std::string& b, size_t* at) {
  const uint64_t n = Le(b, *at, 4);
  if (*at + 4 + n > b.size()) throw std::runtime_error("string past the end");
  std::string s = b.substr(*at + 4, n);
  *at += 4 + n;
  return s;
}
// Records laid end to end in `b` from `at` to `end`; stops at DataEnd (0x0F).
inline void Walk(const std::string& b, size_t at, size_t end, SpecReadResult* r) {
  while (at + 9 <= end) {
    const uint8_t op = static_cast<uint8_t>(b[at]);
    const uint64_t len = Le(b, at + 1, 8);
    const size_t body = at + 9;
    if (body + len > end) break;  // cut short: what came before counts
    if (op == 0x0F) return;
    if (op == 0x03) {
      size_t p = body + 2;
      r->schema_names[static_cast<uint16_t>(Le(b, body, 2))] = Str(b, &p);
    } else if (op == 0x04) {
      const auto id = static_cast<uint16_t>(Le(b, body, 2));
      r->channel_schema[id] = static_cast<uint16_t>(Le(b, body + 2, 2));
      size_t p = body + 4;
      r->topics[id] = Str(b, &p);
    } else if (op == 0x05) {
      const auto id = static_cast<uint16_t>(Le(b, body, 2));
      ++r->counts[r->topics.at(id)];
      ++r->messages;
    } else if (op == 0x06) {
      // start(8) end(8) uncompressed_size(8) crc(4) compression(string) records(uint64 + bytes)
      const uint64_t usize = Le(b, body + 16, 8);
      size_t p = body + 28;
      const std::string compression = Str(b, &p);
      const uint64_t n = Le(b, p, 8);
      std::string records = b.substr(p + 8, n);
      if (compression == "zstd") {
        std::string out(usize, '\0');
        if (ZSTD_decompress(out.data(), usize, records.data(), records.size()) != usize) {
          throw std::runtime_error("bad zstd chunk");
        }
        records = out;
      } else if (!compression.empty()) {
        throw std::runtime_error("unknown compression " + compression);
      }
      ++r->chunks;
      Walk(records, 0, records.size(), r);
    }
    at = body + len;
  }
}
}  // namespace spec_detail

inline SpecReadResult SpecRead(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (b.size() < 8 || b.compare(0, 8, std::string("\x89MCAP0\r\n", 8)) != 0) {
    throw std::runtime_error(path + ": no MCAP magic");
  }
  SpecReadResult r;
  spec_detail::Walk(b, 8, b.size(), &r);
  // Footer: the 29 bytes before the closing magic; summary_start at its byte 9.
  if (b.size() >= 8 + 29 + 8 && b.compare(b.size() - 8, 8, std::string("\x89MCAP0\r\n", 8)) == 0 &&
      static_cast<uint8_t>(b[b.size() - 37]) == 0x02) {
    r.has_footer = true;
    size_t at = spec_detail::Le(b, b.size() - 37 + 9, 8);
    while (at != 0 && at + 9 <= b.size() - 37) {
      const uint8_t op = static_cast<uint8_t>(b[at]);
      const uint64_t len = spec_detail::Le(b, at + 1, 8);
      if (op == 0x0B) r.statistics_message_count = spec_detail::Le(b, at + 9, 8);
      at += 9 + len;
    }
  }
  return r;
}

}  // namespace monocle::testing
