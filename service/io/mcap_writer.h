// Writes an MCAP file (mcap_format.h): messages in chunks (optionally zstd-compressed), each
// chunk followed by its message indexes, and on Close the summary section (schemas,
// channels, statistics, chunk indexes), the summary offsets and the footer, so a reader can
// seek by the index. A chunk reaches the file in one write, so a recording cut short (power,
// SIGKILL) keeps every complete chunk readable by a linear scan (McapReader recovers them).
// Not thread-safe: one thread writes (the recorder's).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "service/common/result.h"
#include "service/io/mcap_format.h"

namespace monocle::mcap {

struct WriterOptions {
  std::string profile = "ros2";                      // the MCAP profile (ROS 2: CDR messages)
  std::string library = "monocle " MONOCLE_VERSION;  // who wrote the file
  size_t chunk_bytes = 1u << 20;  // a chunk is closed once its records reach this
  bool zstd = false;              // compress chunks losslessly with zstd
  int zstd_level = 1;             // fast: a recorder must keep up with the camera
  // Stop writing (a clear error, the summary still written) when the file system has less
  // than this free before a chunk; 0 disables the check.
  uint64_t keep_free_bytes = 16u << 20;
};

class Writer {
 public:
  // Creates (truncates) `path` and writes the magic and the header.
  static Result<std::unique_ptr<Writer>> Create(const std::string& path, WriterOptions options);
  ~Writer();  // closes if Close was not called (errors are then lost: call Close)
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Ids start at 1. The records go into the current chunk (and into the summary on Close).
  uint16_t AddSchema(std::string_view name, std::string_view encoding, std::string_view data);
  uint16_t AddChannel(uint16_t schema_id, std::string_view topic, std::string_view message_encoding,
                      const std::map<std::string, std::string>& metadata = {});

  // Appends one message. Times are nanoseconds since the Unix epoch. After a write error
  // (disk full, file size limit) every call returns that error and nothing more is written;
  // the file keeps everything up to the last complete chunk.
  Status Write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns,
               uint64_t publish_time_ns, std::string_view data);

  // Writes the last chunk, the summary and the footer; the file is then complete. After a
  // write error it still writes the summary of what the file holds, and returns the error.
  Status Close();

  uint64_t bytes_written() const { return file_offset_; }
  // Messages in complete chunks on disk.
  uint64_t message_count() const { return message_count_; }

 private:
  struct ChunkIndexEntry {
    uint64_t start_time, end_time, offset, length, message_index_length, compressed_size,
        uncompressed_size;
    std::map<uint16_t, uint64_t> message_index_offsets;
  };
  Writer(int fd, WriterOptions options);
  Status FlushChunk();
  Status WriteAll(std::string_view bytes);
  void WriteSummaryAndFooter();

  int fd_ = -1;
  WriterOptions options_;
  bool closed_ = false;
  std::optional<Error> failed_;
  uint64_t file_offset_ = 0;
  std::string schema_records_;   // every Schema record, for the summary
  std::string channel_records_;  // every Channel record, for the summary
  uint16_t schema_count_ = 0, channel_count_ = 0;

  // The open chunk.
  Bytes chunk_;
  uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
  bool chunk_has_messages_ = false;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;  // time, offset

  // Statistics of the chunks on disk.
  uint64_t message_count_ = 0, start_time_ = 0, end_time_ = 0;
  std::map<uint16_t, uint64_t> channel_message_counts_;
  std::vector<ChunkIndexEntry> chunk_indexes_;
};

}  // namespace monocle::mcap
