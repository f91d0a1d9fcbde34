#include "service/io/base_trajectory_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "service/io/bounded_file.h"

namespace monocle {
namespace {

constexpr const char* kFieldNames[3] = {"x_m", "y_m", "heading_deg"};

Error LineError(const std::string& source, int line, const std::string& what) {
  return MakeError(ErrorCode::kInvalidArgument,
                   source + ": line " + std::to_string(line) + ": " + what);
}

}  // namespace

Result<std::vector<BasePose2d>> ParseBaseTrajectory(const std::string& text,
                                                    const std::string& source) {
  std::vector<BasePose2d> out;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    if (fields.empty()) continue;
    if (fields.size() != 3) {
      return LineError(
          source, number,
          "expected 3 numbers, x_m y_m heading_deg, found " + std::to_string(fields.size()));
    }
    double v[3];
    for (int i = 0; i < 3; ++i) {
      const std::string& f = fields[i];
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v[i]);
      if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v[i])) {
        return LineError(source, number,
                         std::string(kFieldNames[i]) + " '" + f + "' is not a number");
      }
    }
    out.push_back({v[0], v[1], v[2] * std::numbers::pi / 180});
  }
  if (out.empty()) {
    return MakeError(ErrorCode::kInvalidArgument,
                     source + ": no poses (one a line: x_m y_m heading_deg)");
  }
  return out;
}

Result<std::vector<BasePose2d>> LoadBaseTrajectoryFile(const std::string& path) {
  auto text = ReadBoundedFile(path, "trajectory", kMaxTextFileBytes);
  if (!text) return text.error();
  return ParseBaseTrajectory(*text, path);
}

}  // namespace monocle
