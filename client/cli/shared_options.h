// Options several commands share, declared once: the live forms' DDS options (--domain,
// --timeout, --security) and a chessboard (--board, --square).
#pragma once

#include <optional>
#include <string>

#include "client/cli/command_line.h"
#include "monocle/client.h"
#include "service/vision/chessboard.h"

namespace monocle::cli {

struct LiveOptions {
  std::optional<std::string> camera;
  int domain = 0;
  double timeout_s = 10;
  std::optional<std::string> security_dir;  // else $MONOCLE_SECURITY
};

// --domain, --timeout (seconds, `timeout_help` says what it bounds) and --security, in the
// form being declared. --camera is the command's own (what it means differs).
void DeclareServiceOptions(CommandLine& line, LiveOptions* live, const std::string& timeout_help);

// A client of the running service; on failure prints why and sets *exit_status.
std::optional<Client> OpenClient(const LiveOptions& live, int* exit_status);

struct BoardOptions {
  std::string size;  // COLSxROWS, checked when parsed
  double square_m = 0;
  BoardSpec Spec() const;
};

// --board COLSxROWS and --square METRES, both required where declared.
void DeclareBoard(CommandLine& line, BoardOptions* board);

}  // namespace monocle::cli
