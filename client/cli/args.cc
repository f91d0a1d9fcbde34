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

Result<Args> Args::Parse(const std::vector<std::string>& argv, const ArgSpec& spec) {
  Args args;
  bool only_positionals = false;
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    // "-12.5,3" is a (negative) number, not an option.
    const bool negative_number = a.size() >= 2 && a[0] == '-' &&
                                 (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.');
    if (only_positionals || a.size() < 2 || a[0] != '-' || negative_number) {
      args.positionals_.push_back(a);
      continue;
    }
    if (a == "--") {
      only_positionals = true;
      continue;
    }
    std::string name = a, value;
    bool has_inline_value = false;
    if (const auto eq = a.find('='); eq != std::string::npos) {
      name = a.substr(0, eq);
      value = a.substr(eq + 1);
      has_inline_value = true;
    }
    if (spec.flags.count(name)) {
      if (has_inline_value) return MakeError(ErrorCode::kInvalidArgument, name + " takes no value");
      args.flags_.insert(name);
    } else if (spec.value_options.count(name)) {
      if (!has_inline_value) {
        if (i + 1 >= argv.size())
          return MakeError(ErrorCode::kInvalidArgument, name + " needs a value");
        value = argv[++i];
      }
      args.options_.emplace(name, value);
    } else {
      return MakeError(ErrorCode::kInvalidArgument, "unknown option " + name + " (see --help)");
    }
  }
  return args;
}

bool Args::Has(const std::string& name) const { return flags_.count(name) || options_.count(name); }

std::optional<std::string> Args::Get(const std::string& name) const {
  const auto range = options_.equal_range(name);
  if (range.first == range.second) return std::nullopt;
  return std::prev(range.second)->second;
}

std::vector<std::string> Args::GetAll(const std::string& name) const {
  std::vector<std::string> out;
  const auto range = options_.equal_range(name);
  for (auto it = range.first; it != range.second; ++it) out.push_back(it->second);
  return out;
}

Result<std::string> Args::Require(const std::string& name) const {
  auto v = Get(name);
  if (!v) return MakeError(ErrorCode::kInvalidArgument, "missing " + name + " (see --help)");
  return *v;
}

Result<double> Args::GetDouble(const std::string& name, double fallback) const {
  const auto v = Get(name);
  if (!v) return fallback;
  const auto d = ParseDouble(*v);
  if (!d) return MakeError(ErrorCode::kInvalidArgument, name + " '" + *v + "' is not a number");
  return *d;
}

Result<double> Args::RequireDouble(const std::string& name) const {
  if (!Get(name))
    return MakeError(ErrorCode::kInvalidArgument, "missing " + name + " (see --help)");
  return GetDouble(name, 0);
}

Result<BoardSpec> RequireBoard(const Args& args) {
  const auto board_text = args.Require("--board");
  if (!board_text) return board_text.error();
  const auto square = args.RequireDouble("--square");
  if (!square) return square.error();
  return ParseBoardSize(*board_text, *square);
}

Result<PointArgument> ParsePointArgument(const std::string& text) {
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
  if (at == std::string::npos) return PointArgument{first->first, first->second, std::nullopt};
  const auto second = parse_pixel(text.substr(at + 1));
  if (!second) {
    return MakeError(
        ErrorCode::kInvalidArgument,
        "POINT '" + text + "' is not u,v or u,v@fu,fv (pixels, e.g. 640.5,300@640.5,800)");
  }
  return PointArgument{first->first, first->second, second};
}

}  // namespace monocle::cli
