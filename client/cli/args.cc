#include "client/cli/args.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace monocle::cli {

std::optional<double> ParseDouble(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::vector<double>> ParseNumberList(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    const auto v = ParseDouble(part);
    if (!v) return std::nullopt;
    out.push_back(*v);
  }
  if (!text.empty() && text.back() == ',') return std::nullopt;
  return out;
}

Result<PixelQuery> ParsePointArgument(const std::string& text) {
  const auto at = text.find('@');
  auto parse_pixel = [](const std::string& part) -> std::optional<std::pair<double, double>> {
    const auto nums = ParseNumberList(part);
    if (!nums || nums->size() != 2) return std::nullopt;
    return std::make_pair((*nums)[0], (*nums)[1]);
  };
  const auto first = parse_pixel(text.substr(0, at));
  if (!first) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "POINT '" + text + "' is not u,v or u,v@fu,fv (pixels, e.g. 640.5,800)");
  }
  if (at == std::string::npos) return PixelQuery{first->first, first->second, std::nullopt};
  const auto second = parse_pixel(text.substr(at + 1));
  if (!second) {
    return MakeError(
        ErrorCode::kInvalidArgument,
        "POINT '" + text + "' is not u,v or u,v@fu,fv (pixels, e.g. 640.5,300@640.5,800)");
  }
  return PixelQuery{first->first, first->second,
                    std::array<double, 2>{second->first, second->second}};
}

}  // namespace monocle::cli
