#include "service/io/mcap_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "service/io/mcap_crc.h"
#include "service/io/mcap_format.h"

namespace monocle::mcap {
namespace {

// Far above anything monocle writes (a chunk holds ~1 MB, or one frame); a larger length in
// a file is treated as corruption rather than allocated.
constexpr uint64_t kMaxRecordBytes = 1ull << 30;
constexpr uint64_t kMaxSummaryBytes = 256ull << 20;

bool ParseSchema(std::string_view content, SchemaInfo* s) {
  Cursor c(content);
  s->id = c.U16();
  s->name = std::string(c.String());
  s->encoding = std::string(c.String());
  s->data = std::string(c.String());
  return c.ok() && s->id != 0;
}

bool ParseChannel(std::string_view content, ChannelInfo* ch) {
  Cursor c(content);
  ch->id = c.U16();
  ch->schema_id = c.U16();
  ch->topic = std::string(c.String());
  ch->message_encoding = std::string(c.String());
  ch->metadata = c.StringMap();
  return c.ok();
}

bool ParseMessage(std::string_view content, Message* m) {
  Cursor c(content);
  m->channel_id = c.U16();
  m->sequence = c.U32();
  m->log_time_ns = c.U64();
  m->publish_time_ns = c.U64();
  if (!c.ok()) return false;
  m->data = c.Take(c.remaining());
  return true;
}

void Count(Summary* s, const Message& m) {
  if (s->message_count == 0 || m.log_time_ns < s->start_time_ns) s->start_time_ns = m.log_time_ns;
  if (s->message_count == 0 || m.log_time_ns > s->end_time_ns) s->end_time_ns = m.log_time_ns;
  ++s->message_count;
  ++s->channel_message_counts[m.channel_id];
}

}  // namespace

Reader::Reader(Reader&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)),
      path_(std::move(o.path_)),
      size_(o.size_),
      data_start_(o.data_start_),
      summary_(std::move(o.summary_)),
      chunks_read_(o.chunks_read_) {}

Reader& Reader::operator=(Reader&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
    size_ = o.size_;
    data_start_ = o.data_start_;
    summary_ = std::move(o.summary_);
    chunks_read_ = o.chunks_read_;
  }
  return *this;
}

Reader::~Reader() {
  if (fd_ >= 0) ::close(fd_);
}

Error Reader::Malformed(uint64_t offset, const std::string& what) const {
  return MakeError(ErrorCode::kInvalidArgument, path_ + ": not a valid MCAP file: " + what +
                                                    " (at byte " + std::to_string(offset) + ")");
}

Result<std::string> Reader::ReadAt(uint64_t offset, uint64_t length) const {
  if (offset > size_ || length > size_ - offset)
    return Malformed(offset, "a record runs past the end");
  std::string out(length, '\0');
  size_t done = 0;
  while (done < length) {
    const ssize_t n =
        ::pread(fd_, out.data() + done, length - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return MakeError(ErrorCode::kIo, "cannot read " + path_ + ": " +
                                           (n < 0 ? std::strerror(errno) : "file shrank"));
    }
    done += static_cast<size_t>(n);
  }
  return out;
}

Result<Reader> Reader::Open(const std::string& path) {
  Reader r;
  r.path_ = path;
  r.fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (r.fd_ < 0) {
    return MakeError(ErrorCode::kNotFound, "cannot open " + path + ": " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(r.fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    return MakeError(ErrorCode::kInvalidArgument, path + " is not a regular file");
  }
  r.size_ = static_cast<uint64_t>(st.st_size);
  r.summary_.file_bytes = r.size_;
  if (Status s = r.ReadHeader(); !s) return s.error();

  // The footer and the closing magic, if the file was closed.
  bool closed = false;
  uint64_t summary_start = 0;
  if (r.size_ >= r.data_start_ + kFooterRecordBytes + sizeof kMagic) {
    const uint64_t footer_at = r.size_ - sizeof kMagic - kFooterRecordBytes;
    auto tail = r.ReadAt(footer_at, kFooterRecordBytes + sizeof kMagic);
    if (!tail) return tail.error();
    Cursor c(*tail);
    const uint8_t op = c.U8();
    const uint64_t len = c.U64();
    summary_start = c.U64();
    c.U64();  // summary_offset_start
    c.U32();  // summary_crc (checked with the summary)
    closed = op == kFooter && len == 20 &&
             std::memcmp(tail->data() + kFooterRecordBytes, kMagic, sizeof kMagic) == 0;
  }
  if (closed && summary_start != 0) {
    Status s = r.ReadSummaryFromIndex(summary_start);
    if (s) return r;
    // A damaged summary: the data section still says everything.
    Summary fresh;
    fresh.profile = r.summary_.profile;
    fresh.library = r.summary_.library;
    fresh.file_bytes = r.size_;
    r.summary_ = std::move(fresh);
    r.summary_.recovery_note = "the summary is damaged (" + s.error().message + "); ";
  }
  r.summary_.recovered = !closed;
  if (Status s = r.ScanForSummary(); !s) return s.error();
  return r;
}

Status Reader::ReadHeader() {
  if (size_ < sizeof kMagic + kRecordPrefixBytes) {
    return Malformed(0, "the file is too short for the MCAP magic and header");
  }
  auto head = ReadAt(0, sizeof kMagic + kRecordPrefixBytes);
  if (!head) return head.error();
  if (std::memcmp(head->data(), kMagic, sizeof kMagic) != 0) {
    return Malformed(0, "the file does not start with the MCAP magic");
  }
  Cursor c(std::string_view(*head).substr(sizeof kMagic));
  const uint8_t op = c.U8();
  const uint64_t len = c.U64();
  if (op != kHeader || len > (1u << 20)) return Malformed(sizeof kMagic, "no header record");
  auto content = ReadAt(sizeof kMagic + kRecordPrefixBytes, len);
  if (!content) return content.error();
  Cursor h(*content);
  summary_.profile = std::string(h.String());
  summary_.library = std::string(h.String());
  if (!h.ok()) return Malformed(sizeof kMagic, "header record");
  data_start_ = sizeof kMagic + kRecordPrefixBytes + len;
  return Ok{};
}

Status Reader::ReadSummaryFromIndex(uint64_t summary_start) {
  const uint64_t footer_at = size_ - sizeof kMagic - kFooterRecordBytes;
  if (summary_start < data_start_ || summary_start > footer_at ||
      footer_at - summary_start > kMaxSummaryBytes) {
    return Malformed(footer_at, "footer: summary_start out of range");
  }
  auto summary = ReadAt(summary_start, footer_at - summary_start);
  if (!summary) return summary.error();
  auto footer = ReadAt(footer_at, kFooterRecordBytes);
  if (!footer) return footer.error();
  uint32_t stored_crc = 0;
  std::memcpy(&stored_crc, footer->data() + kFooterRecordBytes - 4, 4);
  if (stored_crc != 0 && Crc32(std::string_view(*footer).substr(0, kFooterRecordBytes - 4),
                               Crc32(*summary)) != stored_crc) {
    return Malformed(summary_start, "summary CRC mismatch");
  }
  bool have_statistics = false;
  Cursor c(*summary);
  while (c.ok() && c.remaining() > 0) {
    const uint64_t at = summary_start + c.position();
    const uint8_t op = c.U8();
    const std::string_view content = c.Take(c.U64());
    if (!c.ok()) return Malformed(at, "summary record runs past the footer");
    bool ok = true;
    if (op == kSchema) {
      SchemaInfo s;
      ok = ParseSchema(content, &s);
      summary_.schemas[s.id] = std::move(s);
    } else if (op == kChannel) {
      ChannelInfo ch;
      ok = ParseChannel(content, &ch);
      summary_.channels[ch.id] = std::move(ch);
    } else if (op == kStatistics) {
      Cursor s(content);
      summary_.message_count = s.U64();
      s.U16();  // schema_count
      s.U32();  // channel_count
      s.U32();  // attachment_count
      s.U32();  // metadata_count
      summary_.chunk_count = s.U32();
      summary_.start_time_ns = s.U64();
      summary_.end_time_ns = s.U64();
      Cursor counts(s.String());
      while (counts.ok() && counts.remaining() > 0) {
        const uint16_t channel = counts.U16();
        const uint64_t n = counts.U64();
        if (counts.ok()) summary_.channel_message_counts[channel] = n;
      }
      ok = s.ok() && counts.ok();
      have_statistics = ok;
    }
    if (!ok) return Malformed(at, "summary record of opcode " + std::to_string(op));
  }
  if (!have_statistics) return Malformed(summary_start, "no statistics in the summary");
  summary_.from_index = true;
  return Ok{};
}

Result<std::string> Reader::ChunkRecords(std::string_view chunk_content, uint64_t offset) {
  Cursor c(chunk_content);
  c.U64();  // message_start_time
  c.U64();  // message_end_time
  const uint64_t uncompressed_size = c.U64();
  const uint32_t crc = c.U32();
  const std::string compression(c.String());
  const std::string_view records = c.Take(c.U64());
  if (!c.ok()) return Malformed(offset, "chunk header");
  if (uncompressed_size > kMaxRecordBytes) return Malformed(offset, "chunk larger than 1 GB");
  std::string out;
  if (compression.empty()) {
    if (records.size() != uncompressed_size) return Malformed(offset, "chunk size mismatch");
    out.assign(records);
  } else if (compression == "zstd") {
    const unsigned long long frame = ZSTD_getFrameContentSize(records.data(), records.size());
    if (frame != uncompressed_size) return Malformed(offset, "zstd chunk size mismatch");
    out.resize(uncompressed_size);
    const size_t n = ZSTD_decompress(out.data(), out.size(), records.data(), records.size());
    if (ZSTD_isError(n) || n != uncompressed_size) return Malformed(offset, "corrupt zstd chunk");
  } else {
    return MakeError(ErrorCode::kOutOfRange,  // not damaged: not to be skipped as damaged
                     path_ + ": chunks compressed with '" + compression +
                         "' are not supported (monocle reads uncompressed and zstd chunks)");
  }
  if (crc != 0 && Crc32(out) != crc) return Malformed(offset, "chunk CRC mismatch");
  ++chunks_read_;
  return out;
}

Reader::MessageStream::MessageStream(Reader* reader, bool skip_damaged_chunks)
    : reader_(reader), offset_(reader->data_start_), skip_damaged_(skip_damaged_chunks) {
  // A damaged chunk may hold the schemas and channels later chunks use: a closed file's
  // summary has them all.
  if (skip_damaged_ && reader->summary_.from_index) {
    schemas_ = reader->summary_.schemas;
    channels_ = reader->summary_.channels;
  }
}

bool Reader::MessageStream::Handle(uint8_t op, std::string_view content,
                                   std::optional<Message>* message) {
  if (op == kSchema) {
    SchemaInfo schema;
    if (!ParseSchema(content, &schema)) return false;
    schemas_[schema.id] = std::move(schema);
  } else if (op == kChannel) {
    ChannelInfo ch;
    if (!ParseChannel(content, &ch)) return false;
    channels_[ch.id] = std::move(ch);
  } else if (op == kMessage) {
    Message m;
    if (!ParseMessage(content, &m)) return false;
    if (channels_.count(m.channel_id) == 0) return false;  // a message before its channel
    *message = m;
  }
  return true;
}

Result<std::optional<Message>> Reader::MessageStream::Next() {
  Reader& r = *reader_;
  while (true) {
    if (in_chunk_) {
      Cursor c(std::string_view(chunk_).substr(chunk_position_));
      if (c.remaining() == 0) {
        in_chunk_ = false;
        ++complete_chunks_;
        continue;
      }
      const uint8_t op = c.U8();
      const std::string_view content = c.Take(c.U64());
      std::optional<Message> message;
      if (!c.ok() || !Handle(op, content, &message)) {
        if (!skip_damaged_) return r.Malformed(chunk_offset_, "a record inside the chunk");
        skipped_.push_back({chunk_offset_, "a damaged record inside it; its rest skipped"});
        in_chunk_ = false;
        continue;
      }
      chunk_position_ += c.position();
      if (message) return message;
      continue;
    }
    if (ended_ || offset_ + kRecordPrefixBytes > r.size_) {
      ended_ = true;
      return std::optional<Message>();
    }
    auto prefix = r.ReadAt(offset_, kRecordPrefixBytes);
    if (!prefix) return prefix.error();
    Cursor p(*prefix);
    const uint8_t op = p.U8();
    const uint64_t len = p.U64();
    if (op == kDataEnd || op == kFooter) {
      ended_ = true;
      continue;
    }
    // Only a cut-short file may end in a broken record; in a closed file it is an error.
    auto broken = [&](const std::string& what) -> Result<std::optional<Message>> {
      if (!r.summary_.recovered) return r.Malformed(offset_, what);
      stopped_early_ = what + " at byte " + std::to_string(offset_);
      ended_ = true;
      return std::optional<Message>();
    };
    const bool cut = len > r.size_ - offset_ - kRecordPrefixBytes;
    if (op == 0 || cut || len > kMaxRecordBytes) {
      return broken(op == 0 ? "an invalid record"
                    : cut   ? "a record cut short"
                            : "a record larger than 1 GB");
    }
    const uint64_t record_at = offset_;
    const uint64_t content_at = offset_ + kRecordPrefixBytes;
    if (op == kChunk) {
      auto content = r.ReadAt(content_at, len);
      if (!content) return content.error();
      auto records = r.ChunkRecords(*content, record_at);
      if (!records && skip_damaged_ && records.error().code == ErrorCode::kInvalidArgument) {
        skipped_.push_back({record_at, records.error().message});
        offset_ = content_at + len;
        continue;
      }
      if (!records) {
        if (!r.summary_.recovered) return records.error();
        return broken("a damaged chunk");
      }
      chunk_ = std::move(*records);
      chunk_position_ = 0;
      chunk_offset_ = record_at;
      in_chunk_ = true;
    } else if (op == kSchema || op == kChannel || op == kMessage) {
      auto content = r.ReadAt(content_at, len);
      if (!content) return content.error();
      record_ = std::move(*content);
      std::optional<Message> message;
      if (!Handle(op, record_, &message)) {
        if (!r.summary_.recovered) {
          return r.Malformed(record_at, "record of opcode " + std::to_string(op));
        }
        return broken("a damaged record");
      }
      offset_ = content_at + len;
      if (message) return message;
      continue;
    }
    // Message indexes, attachments, metadata and unknown records are skipped by length.
    offset_ = content_at + len;
  }
}

Status Reader::ScanForSummary() {
  MessageStream stream(this, /*skip_damaged_chunks=*/false);
  while (true) {
    auto m = stream.Next();
    if (!m) return m.error();
    if (!*m) break;
    Count(&summary_, **m);
  }
  summary_.schemas = stream.schemas();
  summary_.channels = stream.channels();
  summary_.chunk_count = stream.complete_chunks();
  if (!stream.stopped_early().empty()) {
    summary_.recovery_note += stream.stopped_early() + "; kept " +
                              std::to_string(summary_.chunk_count) + " complete chunks before it";
  } else if (summary_.recovered) {
    summary_.recovery_note += "the file was not closed (no footer); kept all " +
                              std::to_string(summary_.chunk_count) + " complete chunks";
  }
  return Ok{};
}

Result<ChunkCheck> Reader::CheckChunks() {
  MessageStream stream(this, /*skip_damaged_chunks=*/true);
  while (true) {
    auto m = stream.Next();
    if (!m) return m.error();
    if (!*m) break;
  }
  ChunkCheck out;
  out.damaged = stream.skipped();
  out.intact = stream.complete_chunks();
  out.stopped_early = stream.stopped_early();
  return out;
}

Status Reader::ForEachMessage(
    const std::function<bool(const ChannelInfo&, const Message&)>& visit) {
  MessageStream stream(this, /*skip_damaged_chunks=*/false);
  while (true) {
    auto m = stream.Next();
    if (!m) return m.error();
    if (!*m || !visit(stream.channel((*m)->channel_id), **m)) return Ok{};
  }
}

}  // namespace monocle::mcap
