// MCAP writer and reader: round trips (plain and zstd), what the index alone answers, files
// cut short at every kind of place, damaged files, and a write that fails half-way (file size
// limit), each checked against the independent reader of tests/mcap_spec_reader.h.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "service/io/mcap_reader.h"
#include "service/io/mcap_writer.h"
#include "tests/mcap_spec_reader.h"

namespace monocle::mcap {
namespace {

struct Written {
  uint16_t channel;
  uint32_t sequence;
  uint64_t log_time, publish_time;
  std::string data;
};

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("mcap_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// Writes `n` messages on three channels, sizes from 0 bytes to 3x the chunk size.
std::vector<Written> WriteFile(const std::string& path, WriterOptions options, int n,
                               uint32_t seed = 1) {
  auto w = Writer::Create(path, options);
  EXPECT_TRUE(w.ok());
  const uint16_t s1 = (*w)->AddSchema("geometry_msgs/msg/Point", "ros2msg", "float64 x\n");
  const uint16_t s2 = (*w)->AddSchema("sensor_msgs/msg/Image", "ros2msg", "uint32 height\n");
  const uint16_t channels[3] = {
      (*w)->AddChannel(s1, "/a/pose", "cdr", {{"offered_qos_profiles", ""}}),
      (*w)->AddChannel(s2, "/a/image_raw", "cdr"),
      (*w)->AddChannel(s1, "/b/pose", "cdr"),
  };
  std::mt19937 rng(seed);
  std::vector<Written> out;
  uint64_t t = 1'700'000'000'000'000'000ull;
  for (int i = 0; i < n; ++i) {
    Written m;
    m.channel = channels[rng() % 3];
    m.sequence = static_cast<uint32_t>(i);
    t += 1 + rng() % 1'000'000;
    m.log_time = t;
    m.publish_time = t - rng() % 1000;
    const size_t size = (i % 97 == 0) ? 3 * options.chunk_bytes : rng() % 300;
    m.data.resize(size);
    for (char& c : m.data) c = static_cast<char>(rng());
    EXPECT_TRUE((*w)->Write(m.channel, m.sequence, m.log_time, m.publish_time, m.data).ok());
    out.push_back(std::move(m));
  }
  EXPECT_TRUE((*w)->Close().ok());
  return out;
}

std::vector<Written> ReadAll(Reader& r) {
  std::vector<Written> got;
  const Status s = r.ForEachMessage([&](const ChannelInfo& ch, const Message& m) {
    EXPECT_EQ(ch.id, m.channel_id);
    got.push_back(
        {m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns, std::string(m.data)});
    return true;
  });
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return got;
}

void ExpectSame(const std::vector<Written>& a, const std::vector<Written>& b, size_t n) {
  ASSERT_GE(a.size(), n);
  ASSERT_GE(b.size(), n);
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(a[i].channel, b[i].channel) << i;
    ASSERT_EQ(a[i].sequence, b[i].sequence) << i;
    ASSERT_EQ(a[i].log_time, b[i].log_time) << i;
    ASSERT_EQ(a[i].publish_time, b[i].publish_time) << i;
    ASSERT_EQ(a[i].data, b[i].data) << i;
  }
}

class McapRoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(McapRoundTrip, EveryMessageComesBackBitForBitAndTheIndexAnswersAlone) {
  const std::string path = TempPath(GetParam() ? "zstd.mcap" : "plain.mcap");
  WriterOptions options;
  options.zstd = GetParam();
  options.chunk_bytes = 16 << 10;
  const std::vector<Written> written = WriteFile(path, options, 2000);

  auto r = Reader::Open(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Summary& s = r->summary();
  EXPECT_TRUE(s.from_index);
  EXPECT_FALSE(s.recovered);
  EXPECT_EQ(r->chunks_read(), 0u) << "the summary must be read without touching a chunk";
  EXPECT_EQ(s.profile, "ros2");
  EXPECT_EQ(s.message_count, written.size());
  EXPECT_EQ(s.channels.size(), 3u);
  EXPECT_EQ(s.schemas.size(), 2u);
  EXPECT_EQ(s.channels.at(1).metadata.count("offered_qos_profiles"), 1u);
  EXPECT_EQ(s.start_time_ns, written.front().log_time);
  EXPECT_EQ(s.end_time_ns, written.back().log_time);
  EXPECT_GT(s.chunk_count, 20u);

  const std::vector<Written> got = ReadAll(*r);
  ASSERT_EQ(got.size(), written.size());
  ExpectSame(got, written, written.size());
  EXPECT_EQ(r->chunks_read(), s.chunk_count);

  // The independent reader sees the same channels, counts and statistics.
  const testing::SpecReadResult spec = testing::SpecRead(path);
  EXPECT_TRUE(spec.has_footer);
  EXPECT_EQ(spec.messages, written.size());
  EXPECT_EQ(spec.statistics_message_count, written.size());
  EXPECT_EQ(spec.chunks, s.chunk_count);
  for (const auto& [id, ch] : s.channels) {
    EXPECT_EQ(spec.topics.at(id), ch.topic);
    EXPECT_EQ(spec.counts.at(ch.topic), s.channel_message_counts.at(id)) << ch.topic;
  }
  std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(PlainAndZstd, McapRoundTrip, ::testing::Bool());

TEST(McapRecovery, AFileCutAnywhereKeepsEveryCompleteChunk) {
  const std::string path = TempPath("whole.mcap");
  WriterOptions options;
  options.zstd = true;
  options.chunk_bytes = 8 << 10;
  const std::vector<Written> written = WriteFile(path, options, 1500, 7);
  std::ifstream in(path, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut_path = TempPath("cut.mcap");
  std::mt19937 rng(3);
  int recovered_files = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // Anywhere from just after the header to just before the footer's magic.
    const size_t cut = 40 + rng() % (whole.size() - 48);
    std::ofstream(cut_path, std::ios::binary | std::ios::trunc).write(whole.data(), cut);
    auto r = Reader::Open(cut_path);
    ASSERT_TRUE(r.ok()) << "cut at " << cut << ": " << r.error().message;
    const testing::SpecReadResult spec = testing::SpecRead(cut_path);
    EXPECT_TRUE(r->summary().recovered) << cut;
    EXPECT_FALSE(r->summary().recovery_note.empty());
    EXPECT_EQ(r->summary().message_count, spec.messages) << "cut at " << cut;
    const std::vector<Written> got = ReadAll(*r);
    EXPECT_EQ(got.size(), r->summary().message_count);
    ExpectSame(got, written, got.size());
    recovered_files += got.empty() ? 0 : 1;
  }
  EXPECT_GT(recovered_files, 30) << "most cuts leave complete chunks to read";
  std::remove(path.c_str());
  std::remove(cut_path.c_str());
}

TEST(McapErrors, DamagedFilesAreRefusedWithTheByteNamed) {
  const std::string path = TempPath("bad.mcap");
  std::ofstream(path) << "this is not an MCAP file at all";
  auto r = Reader::Open(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("MCAP magic"), std::string::npos) << r.error().message;

  // A closed file whose first chunk has a flipped byte: its CRC says so.
  WriterOptions options;
  options.chunk_bytes = 4 << 10;
  WriteFile(path, options, 300);
  std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
  f.seekp(200);
  f.put('\x5a');
  f.close();
  auto damaged = Reader::Open(path);
  ASSERT_TRUE(damaged.ok()) << "the summary alone is intact";
  const Status s = damaged->ForEachMessage([](const ChannelInfo&, const Message&) { return true; });
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("CRC"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("at byte"), std::string::npos) << s.error().message;
  // Checked, the damaged chunk is named and the others read; a stream that skips damaged
  // chunks gives every message of the others, in order.
  const auto check = damaged->CheckChunks();
  ASSERT_TRUE(check.ok()) << check.error();
  ASSERT_EQ(check->damaged.size(), 1u);
  EXPECT_LT(check->damaged[0].offset, 200u) << "the chunk holding byte 200";
  EXPECT_NE(check->damaged[0].why.find("CRC"), std::string::npos) << check->damaged[0].why;
  EXPECT_EQ(check->intact + 1, damaged->summary().chunk_count);
  auto stream = damaged->Messages(/*skip_damaged_chunks=*/true);
  uint64_t read = 0;
  uint32_t last_sequence = 0;
  while (true) {
    auto m = stream.Next();
    ASSERT_TRUE(m.ok()) << m.error();
    if (!*m) break;
    EXPECT_GT((*m)->sequence, last_sequence);
    last_sequence = (*m)->sequence;
    ++read;
  }
  EXPECT_EQ(stream.skipped().size(), 1u);
  EXPECT_GT(read, 0u);
  EXPECT_LT(read, 300u) << "the damaged chunk's messages are missing";
  EXPECT_EQ(last_sequence, 299u) << "and the ones after it are read";

  // A directory, a missing file.
  EXPECT_FALSE(Reader::Open(std::filesystem::temp_directory_path().string()).ok());
  EXPECT_EQ(Reader::Open(path + ".missing").error().code, ErrorCode::kNotFound);
  std::remove(path.c_str());
}

TEST(McapWriteFailure, AFileSizeLimitStopsTheRecordingWithAReadableIndexedFile) {
  const std::string path = TempPath("limited.mcap");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // As a full disk would: writes beyond 300 kB fail (EFBIG instead of ENOSPC).
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{300 << 10, 300 << 10};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    WriterOptions options;
    options.chunk_bytes = 32 << 10;
    auto w = Writer::Create(path, options);
    if (!w) ::_exit(10);
    const uint16_t ch = (*w)->AddChannel(0, "/x", "cdr");
    const std::string payload(1000, 'x');
    int failed_at = -1;
    for (int i = 0; i < 2000 && failed_at < 0; ++i) {
      if (!(*w)->Write(ch, i, i + 1, i + 1, payload)) failed_at = i;
    }
    const Status closed = (*w)->Close();
    // 0: the write failed and Close reported it, as it must.
    ::_exit(failed_at > 0 && !closed.ok() &&
                    closed.error().message.find("size limit") != std::string::npos
                ? 0
                : 11);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);
  auto r = Reader::Open(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->summary().from_index) << "the summary was written after the failure";
  EXPECT_GT(r->summary().message_count, 100u);
  uint64_t n = 0;
  ASSERT_TRUE(r->ForEachMessage([&](const ChannelInfo&, const Message& m) {
                 EXPECT_EQ(m.sequence, n);
                 EXPECT_EQ(m.data, std::string(1000, 'x'));
                 ++n;
                 return true;
               }).ok());
  EXPECT_EQ(n, r->summary().message_count);
  EXPECT_EQ(testing::SpecRead(path).messages, n);
  std::remove(path.c_str());
}

TEST(McapWriteFailure, ANearlyFullDiskStopsBeforeTheDiskIsFull) {
  const std::string path = TempPath("full.mcap");
  WriterOptions options;
  options.chunk_bytes = 1024;
  options.keep_free_bytes = 1ull << 60;  // more than any disk has
  auto w = Writer::Create(path, options);
  ASSERT_TRUE(w.ok());
  const uint16_t ch = (*w)->AddChannel(0, "/x", "cdr");
  const Status s = (*w)->Write(ch, 0, 1, 1, std::string(2000, 'y'));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("nearly full"), std::string::npos) << s.error().message;
  EXPECT_FALSE((*w)->Write(ch, 1, 2, 2, "z").ok()) << "nothing more after the error";
  EXPECT_FALSE((*w)->Close().ok());
  auto r = Reader::Open(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->summary().from_index);
  EXPECT_EQ(r->summary().message_count, 0u);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace monocle::mcap
