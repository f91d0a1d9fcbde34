// The formats of argument values the commands share: numbers, comma lists, and a POINT of
// `monocle floor measure`. The command line itself is declared per command (command_line.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/common/point_query.h"
#include "service/common/result.h"

namespace monocle::cli {

// Parses a finite double; empty on trailing garbage.
std::optional<double> ParseDouble(const std::string& text);
// Splits "a,b,c" into numbers; empty if any part is not a finite number.
std::optional<std::vector<double>> ParseNumberList(const std::string& text);

// A POINT of `monocle floor measure`: "u,v" (a floor pixel) or "u,v@fu,fv" (a pixel standing
// vertically above its foot, the floor pixel fu,fv), pixels.
Result<PixelQuery> ParsePointArgument(const std::string& text);

}  // namespace monocle::cli
