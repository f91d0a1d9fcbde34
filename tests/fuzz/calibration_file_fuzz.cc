// Fuzz target: a calibration file's text (what `--calibration` and monocled's configuration
// point at). Any text gets a calibration or an error; a calibration that parses must be
// usable: it is saved again and must parse to the same values.
#include <cmath>
#include <cstdint>
#include <string>

#include "service/io/calibration_file.h"

#include "tests/fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto parsed = monocle::ParseCalibration(text, "fuzz.pbtxt");
  if (!parsed) {
    FUZZ_CHECK(!parsed.error().message.empty());  // every refusal says why
    return 0;
  }
  // Round trip: what was accepted is written as it would be after a floor calibration.
  const std::string again = monocle::FormatCalibration(*parsed);
  const auto reparsed = monocle::ParseCalibration(again, "fuzz-again.pbtxt");
  FUZZ_CHECK(reparsed.ok());
  FUZZ_CHECK(reparsed->intrinsics.fx == parsed->intrinsics.fx &&
             reparsed->intrinsics.width_px == parsed->intrinsics.width_px &&
             reparsed->floor.has_value() == parsed->floor.has_value());
  return 0;
}
