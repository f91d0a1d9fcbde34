// Every command of the `monocle` tool, declared once: its name, its synopsis and what it is
// for. The top-level usage, `monocle help --list` and the command reference page
// (client/cli/README.md, `monocle help --markdown`) are all generated from this table, and the
// help test walks it, so a command cannot be left out of any of them.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace monocle::cli {

struct CommandForm {
  int group;            // forms of one group are printed together, groups apart
  const char* heading;  // printed above this form's group when not empty
  const char* name;     // the command's words, e.g. "floor calibrate"
  const char* synopsis;
  const char* summary;
};

// In the order the usage prints them; a command with several forms has several entries.
const std::vector<CommandForm>& CommandForms();

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
