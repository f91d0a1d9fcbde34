// The monocle tool's command line, parsed by CLI11 (Debian's libcli11-dev) behind one small
// interface every command uses: positionals, --name VALUE (or --name=VALUE), repeatable
// options and boolean flags; unknown options, missing values and flags given a value are
// errors in monocle's own words (exit status 2 at the caller).
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/vision/chessboard.h"

namespace monocle::cli {

struct ArgSpec {
  std::set<std::string> value_options;  // take a value, e.g. "--board"
  std::set<std::string> flags;          // no value, e.g. "--json"
};

class Args {
 public:
  static Result<Args> Parse(const std::vector<std::string>& argv, const ArgSpec& spec);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool Has(const std::string& name) const;
  std::optional<std::string> Get(const std::string& name) const;  // last occurrence
  std::vector<std::string> GetAll(const std::string& name) const;
  Result<std::string> Require(const std::string& name) const;
  // Parses a finite number; `unit` goes into the error message.
  Result<double> GetDouble(const std::string& name, double fallback) const;
  Result<double> RequireDouble(const std::string& name) const;

 private:
  std::vector<std::string> positionals_;
  std::multimap<std::string, std::string> options_;
  std::set<std::string> flags_;
};

// --board COLSxROWS and --square METRES, both required, as a board spec.
Result<BoardSpec> RequireBoard(const Args& args);

// The camera-to-ceiling distance, metres: --ceiling-distance Z, else `from_calibration` (the
// calibration file's corner { ceiling_distance }). The error says both ways to give it, and
// `also` after them.
Result<double> CeilingDistanceM(const Args& args, std::optional<double> from_calibration,
                                const std::string& calibration_path, const std::string& also = "");

// Parses a finite double; empty on trailing garbage.
std::optional<double> ParseDouble(const std::string& text);
// Splits "a,b,c" into numbers; empty if any part is not a finite number.
std::optional<std::vector<double>> ParseNumberList(const std::string& text);

// A POINT of `monocle floor measure`: "u,v" (a floor pixel) or "u,v@fu,fv" (a pixel standing
// vertically above the floor pixel fu,fv), pixels.
struct PointArgument {
  double u = 0, v = 0;
  std::optional<std::pair<double, double>> floor_px;  // for a pixel above the floor
};
Result<PointArgument> ParsePointArgument(const std::string& text);

}  // namespace monocle::cli
