// The MCAP container format (version 0), written from its published specification
// (https://mcap.dev/spec): opcodes, and the little-endian primitives every record is made of.
// MCAP has no Debian package; monocle's writer and reader (mcap_writer.h, mcap_reader.h) are
// written from the specification alone and checked in the tests against an independent reader.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace monocle::mcap {

// "\x89MCAP0\r\n": at the start and at the end of every file.
inline constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Opcode (1) + content length (8).
inline constexpr size_t kRecordPrefixBytes = 9;
// Footer record: prefix + summary_start (8) + summary_offset_start (8) + summary_crc (4).
inline constexpr size_t kFooterRecordBytes = kRecordPrefixBytes + 20;

// Appends little-endian fields to a byte buffer (the host is little-endian: x86-64, arm64;
// checked at compile time below).
static_assert(std::endian::native == std::endian::little, "MCAP fields are little-endian");

class Bytes {
 public:
  void U8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void U16(uint16_t v) { Raw(&v, 2); }
  void U32(uint32_t v) { Raw(&v, 4); }
  void U64(uint64_t v) { Raw(&v, 8); }
  void String(std::string_view s) {
    U32(static_cast<uint32_t>(s.size()));
    out_.append(s);
  }
  void Raw(const void* p, size_t n) { out_.append(static_cast<const char*>(p), n); }
  void StringMap(const std::map<std::string, std::string>& m) {
    Bytes body;
    for (const auto& [k, v] : m) {
      body.String(k);
      body.String(v);
    }
    String(body.str());
  }
  // A record: opcode, content length, content.
  void Record(Opcode op, std::string_view content) {
    U8(op);
    U64(content.size());
    out_.append(content);
  }
  const std::string& str() const { return out_; }
  std::string& str() { return out_; }
  size_t size() const { return out_.size(); }
  void clear() { out_.clear(); }

 private:
  std::string out_;
};

// Reads little-endian fields from a byte range; every read checks the bounds and a failed
// read leaves `ok()` false (the caller names the record in its error).
class Cursor {
 public:
  explicit Cursor(std::string_view data) : data_(data) {}
  bool ok() const { return ok_; }
  size_t remaining() const { return ok_ ? data_.size() - pos_ : 0; }
  size_t position() const { return pos_; }
  uint8_t U8() { return Fixed<uint8_t>(); }
  uint16_t U16() { return Fixed<uint16_t>(); }
  uint32_t U32() { return Fixed<uint32_t>(); }
  uint64_t U64() { return Fixed<uint64_t>(); }
  std::string_view Take(uint64_t n) {
    if (!ok_ || n > data_.size() - pos_) {
      ok_ = false;
      return {};
    }
    const std::string_view s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::string_view String() { return Take(U32()); }
  std::map<std::string, std::string> StringMap() {
    std::map<std::string, std::string> m;
    Cursor body(Take(U32()));
    while (ok_ && body.ok() && body.remaining() > 0) {
      const std::string_view k = body.String();
      const std::string_view v = body.String();
      if (body.ok()) m.emplace(std::string(k), std::string(v));
    }
    ok_ = ok_ && body.ok();
    return m;
  }

 private:
  template <typename T>
  T Fixed() {
    T v{};
    const std::string_view s = Take(sizeof(T));
    if (ok_) std::memcpy(&v, s.data(), sizeof(T));
    return v;
  }
  std::string_view data_;
  size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace monocle::mcap
