// Every command of the `monocle` tool, listed once: its name and what it is for. The top-level
// usage, `monocle help --list` and the command reference page (client/cli/README.md, `monocle
// help --markdown`) are generated from this table and each command's own declarations (its
// --help), and the help test walks it, so a command cannot be left out of any of them.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace monocle::cli {

struct CommandEntry {
  const char* heading;  // printed above this command when not empty: a new group starts
  const char* name;     // the command's words, e.g. "floor calibrate"
  const char* summary;  // what it is for, one or two lines
};

// In the order the usage prints them.
const std::vector<CommandEntry>& Commands();

// Each command once, in table order.
std::vector<std::string> CommandNames();

// The usage `monocle --help` prints.
std::string TopLevelUsage();

// Runs `monocle ARGS...`: the command's exit status.
int RunCommand(const std::vector<std::string>& args);

// `monocle help [--list | --markdown]`: the usage, the command names, or the reference page
// made of every command's own --help.
int HelpCommand(const std::vector<std::string>& args);

}  // namespace monocle::cli
