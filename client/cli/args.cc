#include "client/cli/args.h"

#include <CLI/CLI.hpp>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
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
  // CLI11 reads a flag given a value ("--json=1") as set; monocle's flags take none.
  for (const auto& a : argv) {
    if (a == "--") break;
    if (const auto eq = a.find('='); eq != std::string::npos && spec.flags.count(a.substr(0, eq)))
      return MakeError(ErrorCode::kInvalidArgument, a.substr(0, eq) + " takes no value");
  }
  CLI::App app;
  app.set_help_flag();  // each command prints its own help before parsing (WantsHelp)
  app.allow_extras();   // unknown options are reported below, in monocle's words
  // Every value option may repeat (--box ... --box ...); each occurrence takes one value.
  std::map<std::string, std::vector<std::string>> values;
  for (const auto& name : spec.value_options) {
    app.add_option(name, values[name])
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  }
  std::map<std::string, CLI::Option*> flags;
  for (const auto& name : spec.flags) flags[name] = app.add_flag(name);
  // Positionals, in order; "-12.5,3" is a (negative) number, not an option.
  std::vector<std::string> positionals;
  app.add_option("positionals", positionals);
  try {
    // CLI11 takes a vector argument list last-first.
    app.parse(std::vector<std::string>(argv.rbegin(), argv.rend()));
  } catch (const CLI::ArgumentMismatch& e) {
    const std::string what = e.what();
    return MakeError(ErrorCode::kInvalidArgument,
                     what.substr(0, what.find(':')) + " needs a value");
  } catch (const CLI::ParseError& e) {
    return MakeError(ErrorCode::kInvalidArgument, std::string(e.what()) + " (see --help)");
  }
  for (const auto& extra : app.remaining()) {
    if (extra == "--") continue;
    return MakeError(ErrorCode::kInvalidArgument,
                     "unknown option " + extra.substr(0, extra.find('=')) + " (see --help)");
  }
  Args args;
  args.positionals_ = std::move(positionals);
  for (const auto& [name, given] : values)
    for (const auto& v : given) args.options_.emplace(name, v);
  for (const auto& [name, option] : flags)
    if (option->count() > 0) args.flags_.insert(name);
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

Result<double> CeilingDistanceM(const Args& args, std::optional<double> from_calibration,
                                const std::string& calibration_path, const std::string& also) {
  if (args.Get("--ceiling-distance")) {
    const auto z = args.GetDouble("--ceiling-distance", 0);
    if (!z || !(*z > 0))
      return MakeError(ErrorCode::kInvalidArgument,
                       "--ceiling-distance must be a positive distance in metres");
    return *z;
  }
  if (from_calibration && *from_calibration > 0) return *from_calibration;
  return MakeError(ErrorCode::kInvalidArgument,
                   "the camera-to-ceiling distance is unknown: give --ceiling-distance Z (metres) "
                   "or add corner { ceiling_distance: Z } to " +
                       calibration_path + also);
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
