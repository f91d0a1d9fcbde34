#include "service/io/mcap_writer.h"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>

#include "service/io/mcap_crc.h"

namespace monocle::mcap {
namespace {

std::string WriteErrorMessage(int err) {
  if (err == ENOSPC) return "the disk is full";
  if (err == EFBIG) return "the file reached the size limit of this process or file system";
  return std::strerror(err);
}

}  // namespace

Result<std::unique_ptr<Writer>> Writer::Create(const std::string& path, WriterOptions options) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    return MakeError(ErrorCode::kIo,
                     "cannot create recording " + path + ": " + std::strerror(errno));
  }
  std::unique_ptr<Writer> w(new Writer(fd, std::move(options)));
  Bytes head;
  head.Raw(kMagic, sizeof kMagic);
  Bytes header;
  header.String(w->options_.profile);
  header.String(w->options_.library);
  head.Record(kHeader, header.str());
  if (Status s = w->WriteAll(head.str()); !s) return s.error();
  return w;
}

Writer::Writer(int fd, WriterOptions options) : fd_(fd), options_(std::move(options)) {}

Writer::~Writer() {
  if (!closed_) (void)Close();
}

uint16_t Writer::AddSchema(std::string_view name, std::string_view encoding,
                           std::string_view data) {
  const uint16_t id = ++schema_count_;
  Bytes content;
  content.U16(id);
  content.String(name);
  content.String(encoding);
  content.String(data);  // uint32 length-prefixed bytes
  Bytes record;
  record.Record(kSchema, content.str());
  chunk_.str() += record.str();
  schema_records_ += record.str();
  return id;
}

uint16_t Writer::AddChannel(uint16_t schema_id, std::string_view topic,
                            std::string_view message_encoding,
                            const std::map<std::string, std::string>& metadata) {
  const uint16_t id = ++channel_count_;
  Bytes content;
  content.U16(id);
  content.U16(schema_id);
  content.String(topic);
  content.String(message_encoding);
  content.StringMap(metadata);
  Bytes record;
  record.Record(kChannel, content.str());
  chunk_.str() += record.str();
  channel_records_ += record.str();
  return id;
}

Status Writer::Write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
                     uint64_t publish_time_ns, std::string_view data) {
  if (failed_) return *failed_;
  if (closed_) return MakeError(ErrorCode::kIo, "the recording is closed");
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  chunk_.U8(kMessage);
  chunk_.U64(2 + 4 + 8 + 8 + data.size());
  chunk_.U16(channel_id);
  chunk_.U32(sequence);
  chunk_.U64(log_time_ns);
  chunk_.U64(publish_time_ns);
  chunk_.Raw(data.data(), data.size());
  if (!chunk_has_messages_ || log_time_ns < chunk_start_time_) chunk_start_time_ = log_time_ns;
  if (!chunk_has_messages_ || log_time_ns > chunk_end_time_) chunk_end_time_ = log_time_ns;
  chunk_has_messages_ = true;
  if (chunk_.size() >= options_.chunk_bytes) return FlushChunk();
  return Ok{};
}

Status Writer::WriteAll(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return MakeError(ErrorCode::kIo,
                       "cannot write the recording: " + WriteErrorMessage(n < 0 ? errno : ENOSPC));
    }
    bytes.remove_prefix(static_cast<size_t>(n));
    file_offset_ += static_cast<uint64_t>(n);
  }
  return Ok{};
}

Status Writer::FlushChunk() {
  if (chunk_.size() == 0) return Ok{};
  const std::string& records = chunk_.str();
  std::string compressed;
  std::string_view stored = records;
  if (options_.zstd) {
    compressed.resize(ZSTD_compressBound(records.size()));
    const size_t n = ZSTD_compress(compressed.data(), compressed.size(), records.data(),
                                   records.size(), options_.zstd_level);
    if (ZSTD_isError(n)) {
      failed_ = MakeError(ErrorCode::kIo, std::string("zstd failed: ") + ZSTD_getErrorName(n));
      return *failed_;
    }
    compressed.resize(n);
    stored = compressed;
  }
  Bytes content;
  content.U64(chunk_has_messages_ ? chunk_start_time_ : 0);
  content.U64(chunk_has_messages_ ? chunk_end_time_ : 0);
  content.U64(records.size());
  content.U32(Crc32(records));
  content.String(options_.zstd ? "zstd" : "");
  content.U64(stored.size());
  Bytes out;
  out.U8(kChunk);
  out.U64(content.size() + stored.size());
  out.str() += content.str();
  out.str().append(stored);
  ChunkIndexEntry entry{};
  entry.start_time = chunk_has_messages_ ? chunk_start_time_ : 0;
  entry.end_time = chunk_has_messages_ ? chunk_end_time_ : 0;
  entry.offset = file_offset_;
  entry.length = out.size();
  entry.compressed_size = stored.size();
  entry.uncompressed_size = records.size();
  for (const auto& [channel, times_offsets] : chunk_index_) {
    entry.message_index_offsets[channel] = file_offset_ + out.size();
    Bytes index;
    index.U16(channel);
    index.U32(static_cast<uint32_t>(times_offsets.size() * 16));
    for (const auto& [time, offset] : times_offsets) {
      index.U64(time);
      index.U64(offset);
    }
    out.Record(kMessageIndex, index.str());
  }
  entry.message_index_length = out.size() - entry.length;

  if (options_.keep_free_bytes > 0) {
    struct statvfs fs {};
    if (::fstatvfs(fd_, &fs) == 0 &&
        static_cast<uint64_t>(fs.f_bavail) * fs.f_frsize < out.size() + options_.keep_free_bytes) {
      failed_ =
          MakeError(ErrorCode::kIo,
                    "recording stopped: the disk is nearly full (" +
                        std::to_string(static_cast<uint64_t>(fs.f_bavail) * fs.f_frsize >> 20) +
                        " MB free); free space and record again");
      return *failed_;
    }
  }
  const uint64_t good_end = file_offset_;
  if (Status s = WriteAll(out.str()); !s) {
    // Cut the partial chunk off, so the summary follows the last complete one.
    if (::ftruncate(fd_, static_cast<off_t>(good_end)) == 0 &&
        ::lseek(fd_, static_cast<off_t>(good_end), SEEK_SET) >= 0) {
      file_offset_ = good_end;
    }
    failed_ = MakeError(ErrorCode::kIo, "recording stopped: " + s.error().message);
    return *failed_;
  }
  // Only what reached the file counts in the statistics.
  for (const auto& [channel, times_offsets] : chunk_index_) {
    if (message_count_ == 0 || chunk_start_time_ < start_time_) start_time_ = chunk_start_time_;
    if (message_count_ == 0 || chunk_end_time_ > end_time_) end_time_ = chunk_end_time_;
    message_count_ += times_offsets.size();
    channel_message_counts_[channel] += times_offsets.size();
  }
  chunk_indexes_.push_back(std::move(entry));
  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
  return Ok{};
}

void Writer::WriteSummaryAndFooter() {
  Bytes tail;
  tail.U8(kDataEnd);
  tail.U64(4);
  tail.U32(0);  // data section CRC not computed (the chunks carry their own)
  const uint64_t summary_start = file_offset_ + tail.size();
  Bytes summary;
  std::vector<std::tuple<Opcode, uint64_t, uint64_t>> groups;  // opcode, start, length
  auto group = [&](Opcode op, const std::string& records) {
    if (records.empty()) return;
    groups.emplace_back(op, summary_start + summary.size(), records.size());
    summary.str() += records;
  };
  group(kSchema, schema_records_);
  group(kChannel, channel_records_);
  Bytes stats;
  stats.U64(message_count_);
  stats.U16(schema_count_);
  stats.U32(channel_count_);
  stats.U32(0);  // attachments
  stats.U32(0);  // metadata
  stats.U32(static_cast<uint32_t>(chunk_indexes_.size()));
  stats.U64(start_time_);
  stats.U64(end_time_);
  Bytes counts;
  for (const auto& [channel, n] : channel_message_counts_) {
    counts.U16(channel);
    counts.U64(n);
  }
  stats.String(counts.str());
  Bytes stats_record;
  stats_record.Record(kStatistics, stats.str());
  group(kStatistics, stats_record.str());
  Bytes chunk_index_records;
  for (const ChunkIndexEntry& c : chunk_indexes_) {
    Bytes e;
    e.U64(c.start_time);
    e.U64(c.end_time);
    e.U64(c.offset);
    e.U64(c.length);
    Bytes offsets;
    for (const auto& [channel, offset] : c.message_index_offsets) {
      offsets.U16(channel);
      offsets.U64(offset);
    }
    e.String(offsets.str());
    e.U64(c.message_index_length);
    e.String(options_.zstd ? "zstd" : "");
    e.U64(c.compressed_size);
    e.U64(c.uncompressed_size);
    chunk_index_records.Record(kChunkIndex, e.str());
  }
  group(kChunkIndex, chunk_index_records.str());
  const uint64_t summary_offset_start = summary_start + summary.size();
  for (const auto& [op, start, length] : groups) {
    Bytes so;
    so.U8(op);
    so.U64(start);
    so.U64(length);
    summary.Record(kSummaryOffset, so.str());
  }
  Bytes footer_fields;
  footer_fields.U64(summary_start);
  footer_fields.U64(summary_offset_start);
  // CRC of the summary, the summary offsets and the footer up to this field.
  Bytes footer_prefix;
  footer_prefix.U8(kFooter);
  footer_prefix.U64(20);
  footer_prefix.str() += footer_fields.str();
  const uint32_t crc = Crc32(footer_prefix.str(), Crc32(summary.str()));
  tail.str() += summary.str();
  tail.str() += footer_prefix.str();
  tail.U32(crc);
  tail.Raw(kMagic, sizeof kMagic);
  if (Status s = WriteAll(tail.str()); !s && !failed_) failed_ = s.error();
}

Status Writer::Close() {
  if (closed_) return failed_ ? Status(*failed_) : Status(Ok{});
  if (!failed_) (void)FlushChunk();
  // Even after a failure the summary of what is in the file is written: the writer cut the
  // failed chunk off, which gave back at least its size.
  WriteSummaryAndFooter();
  if (::fsync(fd_) != 0 && !failed_) {
    failed_ = MakeError(ErrorCode::kIo,
                        std::string("cannot sync the recording: ") + std::strerror(errno));
  }
  ::close(fd_);
  fd_ = -1;
  closed_ = true;
  return failed_ ? Status(*failed_) : Status(Ok{});
}

}  // namespace monocle::mcap
