#include "client/cli/shared_options.h"

#include <chrono>
#include <cstdlib>
#include <iostream>

#include "client/cli/commands.h"
#include "client/cli/live.h"

namespace monocle::cli {

void DeclareServiceOptions(CommandLine& line, LiveOptions* live, const std::string& timeout_help) {
  line.Whole("--domain", &live->domain, "D", "DDS domain id", In("").Between(0, 232));
  line.Number("--timeout", &live->timeout_s, "S", timeout_help, In("seconds").Above(0));
  line.Text("--security", &live->security_dir, "DIR",
            "this client's identity of a secured service's keystore (`monocle security init`; "
            "default $MONOCLE_SECURITY)");
}

std::optional<Client> OpenClient(const LiveOptions& live, int* exit_status) {
  Client::Options options;
  options.domain = live.domain;
  options.timeout = std::chrono::milliseconds(static_cast<int64_t>(live.timeout_s * 1000));
  if (live.security_dir) {
    options.security_dir = *live.security_dir;
  } else if (const char* env = std::getenv("MONOCLE_SECURITY"); env != nullptr && *env != 0) {
    options.security_dir = env;
  }
  // Data a stranger put on a camera's topics is never shown as the camera's; the user is told.
  options.on_ignored = [](const std::string& what) {
    std::cerr << "monocle: warning: " << what << std::endl;
  };
  auto client = Client::open(options);
  if (!client) {
    *exit_status = Fail(client.error());
    return std::nullopt;
  }
  return std::move(client).value();
}

BoardSpec BoardOptions::Spec() const {
  // Checked as the options were parsed (DeclareBoard).
  return *ParseBoardSize(size, square_m);
}

void DeclareBoard(CommandLine& line, BoardOptions* board) {
  line.Custom("--board", "COLSxROWS", "inner corners of the board, e.g. 9x6",
              [board](const std::string& text) -> std::optional<std::string> {
                if (auto spec = ParseBoardSize(text, 1.0); !spec) return spec.error().message;
                board->size = text;
                return std::nullopt;
              });
  line.Require("--board");
  line.Number("--square", &board->square_m, "METRES", "side of one square", In("metres").Above(0));
  line.Require("--square");
}

}  // namespace monocle::cli
