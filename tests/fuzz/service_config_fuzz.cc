// Fuzz target: monocled's configuration text. Any text gets a setup or an error naming
// where; nothing is opened (calibration files are checked when the service starts).
#include <cstdint>
#include <string>

#include "service/server/service_config.h"

#include "tests/fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto setup = monocle::ParseServiceConfig(text, "fuzz.pbtxt", "/nonexistent");
  if (!setup) {
    FUZZ_CHECK(!setup.error().message.empty());
    return 0;
  }
  // What was accepted holds the limits the service relies on.
  FUZZ_CHECK(setup->cameras.size() <= static_cast<size_t>(monocle::kMaxCamerasPerService));
  for (const auto& c : setup->cameras)
    FUZZ_CHECK(!c.id.empty() && c.id.size() <= monocle::kMaxNameLength);
  return 0;
}
