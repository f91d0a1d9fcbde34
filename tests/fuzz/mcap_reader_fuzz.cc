// Fuzz target: an MCAP recording (`monocle info`, `monocle replay`, `monocled --replay` read
// files from anywhere). Any bytes give a summary or an error saying why, never a crash or a
// hang; a message is never larger than the file, and the two ways of walking the messages
// (visited and pulled) agree on how many there are when both reach the end.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "service/io/mcap_reader.h"
#include "tests/fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The reader takes a path, as its users give it one.
  static const std::string path = "/tmp/monocle_mcap_fuzz_" + std::to_string(getpid()) + ".mcap";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  auto reader = monocle::mcap::Reader::Open(path);
  if (!reader) {
    FUZZ_CHECK(!reader.error().message.empty());  // every refusal says why
    return 0;
  }
  uint64_t visited = 0;
  const auto walked = reader->ForEachMessage(
      [&](const monocle::mcap::ChannelInfo&, const monocle::mcap::Message& m) {
        FUZZ_CHECK(m.data.size() <= size);  // a message is never larger than the file
        ++visited;
        return true;
      });
  if (!walked) FUZZ_CHECK(!walked.error().message.empty());
  uint64_t pulled = 0;
  bool pulled_all = true;
  auto stream = reader->Messages();
  while (true) {
    auto next = stream.Next();
    if (!next) {
      FUZZ_CHECK(!next.error().message.empty());
      pulled_all = false;
      break;
    }
    if (!next->has_value()) break;
    FUZZ_CHECK((*next)->data.size() <= size);
    ++pulled;
  }
  if (walked && pulled_all) FUZZ_CHECK(pulled == visited);
  return 0;
}
