// Reads an MCAP file (mcap_format.h). A complete file is summarised from its summary section
// alone (schemas, channels, statistics, chunk index: no chunk is read); a file that was cut
// short (a recorder killed, a full disk) has no footer and is summarised by one linear scan
// that keeps every complete chunk and says what it dropped. Nothing in the file is trusted:
// every length is checked against the file before anything is allocated.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "service/common/result.h"

namespace monocle::mcap {

struct SchemaInfo {
  uint16_t id = 0;
  std::string name;      // e.g. geometry_msgs/msg/PoseWithCovarianceStamped
  std::string encoding;  // e.g. ros2msg
  std::string data;
};

struct ChannelInfo {
  uint16_t id = 0;
  uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;  // e.g. cdr
  std::map<std::string, std::string> metadata;
};

struct Summary {
  std::string profile, library;
  std::map<uint16_t, SchemaInfo> schemas;
  std::map<uint16_t, ChannelInfo> channels;
  uint64_t message_count = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
  uint64_t start_time_ns = 0, end_time_ns = 0;  // log times; 0 with no messages
  uint64_t chunk_count = 0;
  uint64_t file_bytes = 0;
  bool from_index = false;  // read from the summary section, without reading any chunk
  // A file without a valid footer: what the linear scan kept and dropped.
  bool recovered = false;
  std::string recovery_note;
};

// A chunk that could not be read (a flipped byte, a broken compression) and why.
struct DamagedChunk {
  uint64_t offset = 0;  // of its record in the file
  std::string why;
};

// Every chunk read: how many were intact, which were damaged, and for a cut-short file where
// its walk ended.
struct ChunkCheck {
  uint64_t intact = 0;
  std::vector<DamagedChunk> damaged;
  std::string stopped_early;
};

struct Message {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0;
  uint64_t publish_time_ns = 0;
  std::string_view data;  // valid during the callback only
};

class Reader {
 public:
  // Opens `path` and reads its summary (from the index, or by a scan if the file was cut
  // short). Errors name the file and the byte offset of the first record that is wrong.
  static Result<Reader> Open(const std::string& path);
  Reader(Reader&&) noexcept;
  Reader& operator=(Reader&&) noexcept;
  ~Reader();

  const Summary& summary() const { return summary_; }

  // Every message in file order; `visit` returns false to stop. Only complete chunks of a
  // cut-short file are visited.
  Status ForEachMessage(const std::function<bool(const ChannelInfo&, const Message&)>& visit);

  // Reads and checks every chunk (decompressed, its CRC, its records), going on past damaged
  // ones. An error only for what no reader gets past (the file unreadable, an unsupported
  // compression).
  Result<ChunkCheck> CheckChunks();

  // The messages in file order, one at a time, for a reader that pulls (a replayed camera):
  // one chunk is held decompressed at a time. The Reader must outlive the stream and stay
  // where it is (not be moved) while the stream is used. With `skip_damaged_chunks`, a chunk
  // that cannot be read is passed over (and listed in skipped()) instead of ending the walk
  // with an error.
  class MessageStream {
   public:
    // The next message, nullopt at the end (of the data section, or of the complete chunks of
    // a cut-short file). `Message::data` stays valid until the next call.
    Result<std::optional<Message>> Next();
    // The channel of a message returned by Next().
    const ChannelInfo& channel(uint16_t id) const { return channels_.at(id); }
    const std::map<uint16_t, SchemaInfo>& schemas() const { return schemas_; }
    const std::map<uint16_t, ChannelInfo>& channels() const { return channels_; }
    uint64_t complete_chunks() const { return complete_chunks_; }
    // Why a cut-short file's walk ended before the end of its data ("" if it did not).
    const std::string& stopped_early() const { return stopped_early_; }
    // The damaged chunks passed over so far (skip_damaged_chunks only).
    const std::vector<DamagedChunk>& skipped() const { return skipped_; }

   private:
    friend class Reader;
    MessageStream(Reader* reader, bool skip_damaged_chunks);
    // A schema, channel or message record; false: malformed.
    bool Handle(uint8_t op, std::string_view content, std::optional<Message>* message);

    Reader* reader_;
    uint64_t offset_;     // the next record of the data section
    std::string record_;  // the last message record read outside a chunk
    std::string chunk_;   // the records of the chunk being walked
    size_t chunk_position_ = 0;
    uint64_t chunk_offset_ = 0;
    bool in_chunk_ = false, ended_ = false;
    std::map<uint16_t, SchemaInfo> schemas_;
    std::map<uint16_t, ChannelInfo> channels_;  // as met in the data section
    uint64_t complete_chunks_ = 0;
    std::string stopped_early_;
    bool skip_damaged_ = false;
    std::vector<DamagedChunk> skipped_;
  };
  MessageStream Messages(bool skip_damaged_chunks = false) {
    return MessageStream(this, skip_damaged_chunks);
  }

  // How many chunks were decompressed or scanned so far (0 after Open of a complete file).
  uint64_t chunks_read() const { return chunks_read_; }

 private:
  Reader() = default;
  Status ReadHeader();
  Status ReadSummaryFromIndex(uint64_t summary_start);
  // The summary of a file without a usable index, from one walk over its data section.
  Status ScanForSummary();
  Result<std::string> ReadAt(uint64_t offset, uint64_t length) const;
  Result<std::string> ChunkRecords(std::string_view chunk_content, uint64_t offset);
  Error Malformed(uint64_t offset, const std::string& what) const;

  int fd_ = -1;
  std::string path_;
  uint64_t size_ = 0;
  uint64_t data_start_ = 0;  // after magic and header
  Summary summary_;
  uint64_t chunks_read_ = 0;
};

}  // namespace monocle::mcap
