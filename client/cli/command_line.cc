#include "client/cli/command_line.h"

#include <bit>
#include <cmath>
#include <iostream>
#include <set>
#include <sstream>

#include "client/cli/args.h"

namespace monocle::cli {
namespace {

constexpr size_t kHelpWidth = 96;
constexpr size_t kLabelWidth = 25;  // "  --calibration CAL.pbtxt" and the space after it

}  // namespace

std::string WrapText(const std::string& text, size_t first_column, size_t indent, size_t width) {
  std::ostringstream out;
  std::istringstream words(text);
  size_t column = first_column;
  bool first = true;
  for (std::string word; words >> word;) {
    if (!first && column + 1 + word.size() > width) {
      out << "\n" << std::string(indent, ' ');
      column = indent;
    } else if (!first) {
      out << ' ';
      ++column;
    }
    out << word;
    column += word.size();
    first = false;
  }
  return out.str();
}

namespace {

std::string Joined(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (const auto& part : parts) out += (out.empty() ? "" : separator) + part;
  return out;
}

// "a number of pixels >= 0", "a whole number of frames from 1 to 1e+06".
std::string NumberRule(const NumberCheck& c) {
  std::string rule = std::string(c.whole ? "a whole number" : "a number") +
                     (c.unit.empty() ? "" : " of " + c.unit);
  if (c.min && c.max) return rule + " from " + NumberText(*c.min) + " to " + NumberText(*c.max);
  if (c.min) return rule + (c.above_min ? " > " : " >= ") + NumberText(*c.min);
  if (c.max) return rule + " <= " + NumberText(*c.max);
  return rule;
}

std::optional<std::string> CheckNumber(const std::string& flag, const std::string& text,
                                       const NumberCheck& c, double* value) {
  const auto v = ParseDouble(text);
  const bool fits = v && (!c.min || (c.above_min ? *v > *c.min : *v >= *c.min)) &&
                    (!c.max || *v <= *c.max) &&
                    (!c.whole || (*v == std::floor(*v) && std::abs(*v) <= 1e9));
  if (!fits) return flag + " must be " + NumberRule(c) + ", not '" + text + "'";
  *value = *v;
  return std::nullopt;
}

}  // namespace

std::string NumberText(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

CommandLine::CommandLine(std::string name, std::string about)
    : name_(std::move(name)), about_(std::move(about)) {
  app_.set_help_flag();  // Parse prints the generated help itself
  app_.allow_extras();   // unknown options are reported in monocle's words
  app_.add_option("positionals", positionals_);
}

int CommandLine::Form(std::string heading, std::string why_apart) {
  form_headings_.push_back(std::move(heading));
  form_why_apart_.push_back(std::move(why_apart));
  const int form = static_cast<int>(form_headings_.size()) - 1;
  declaring_forms_ = 1u << form;
  return form;
}

void CommandLine::InForms(std::initializer_list<int> forms) {
  declaring_forms_ = 0;
  for (int f : forms) declaring_forms_ |= 1u << f;
}

CommandLine::Declared& CommandLine::Declare(const std::string& flag, std::string value_name,
                                            std::string help) {
  Declared d;
  d.flag = flag;
  d.value_name = std::move(value_name);
  d.help = std::move(help);
  d.forms = declaring_forms_;
  declared_.push_back(std::move(d));
  return declared_.back();
}

const CommandLine::Declared* CommandLine::Find(const std::string& flag) const {
  for (const auto& d : declared_)
    if (!d.positional && d.flag == flag) return &d;
  return nullptr;
}

void CommandLine::Positionals(std::string value_name, std::vector<std::string>* into,
                              std::string help, size_t at_least, size_t at_most) {
  Declared& d = Declare(value_name, value_name, std::move(help));
  d.positional = true;
  d.at_least = at_least;
  d.at_most = at_most;
  d.positionals_into = into;
}

CLI::Option* CommandLine::Custom(
    const std::string& flag, std::string value_name, std::string help,
    std::function<std::optional<std::string>(const std::string&)> assign) {
  Declared& d = Declare(flag, std::move(value_name), std::move(help));
  // Given more than once, the last occurrence counts.
  d.option = app_.add_option_function<std::string>(flag,
                                                   [flag, assign](const std::string& text) {
                                                     if (auto wrong = assign(text))
                                                       throw CLI::ValidationError(flag, *wrong);
                                                   })
                 ->allow_extra_args(false)
                 ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  return d.option;
}

CLI::Option* CommandLine::CustomRepeated(
    const std::string& flag, std::string value_name, std::string help,
    std::function<std::optional<std::string>(const std::string&)> assign) {
  Declared& d = Declare(flag, std::move(value_name), std::move(help));
  d.repeatable = true;
  d.option = app_.add_option_function<std::vector<std::string>>(
                     flag,
                     [flag, assign](const std::vector<std::string>& texts) {
                       for (const auto& text : texts)
                         if (auto wrong = assign(text)) throw CLI::ValidationError(flag, *wrong);
                     })
                 ->allow_extra_args(false)
                 ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  return d.option;
}

CLI::Option* CommandLine::Text(const std::string& flag, std::string* into, std::string value_name,
                               std::string help) {
  return Custom(flag, std::move(value_name), std::move(help), [into](const std::string& text) {
    *into = text;
    return std::optional<std::string>();
  });
}

CLI::Option* CommandLine::Text(const std::string& flag, std::optional<std::string>* into,
                               std::string value_name, std::string help) {
  return Custom(flag, std::move(value_name), std::move(help), [into](const std::string& text) {
    *into = text;
    return std::optional<std::string>();
  });
}

CLI::Option* CommandLine::Texts(const std::string& flag, std::vector<std::string>* into,
                                std::string value_name, std::string help) {
  Declared& d = Declare(flag, std::move(value_name), std::move(help));
  d.repeatable = true;
  d.option = app_.add_option(flag, *into)
                 ->allow_extra_args(false)
                 ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  return d.option;
}

CLI::Option* CommandLine::Choice(const std::string& flag, std::string* into,
                                 std::vector<std::string> choices, std::string help) {
  const std::string default_text = *into;
  CLI::Option* option =
      Custom(flag, Joined(choices, "|"), std::move(help),
             [flag, into, choices](const std::string& given) -> std::optional<std::string> {
               for (const auto& c : choices) {
                 if (c != given) continue;
                 *into = given;
                 return std::nullopt;
               }
               return "'" + given + "' is not one of " + Joined(choices, ", ");
             });
  declared_.back().default_text = default_text;
  return option;
}

CLI::Option* CommandLine::NumberOption(const std::string& flag, std::string value_name,
                                       std::string help, NumberCheck check,
                                       std::function<void(double)> store,
                                       std::optional<double> default_value) {
  CLI::Option* option =
      Custom(flag, std::move(value_name), std::move(help),
             [flag, check, store](const std::string& text) -> std::optional<std::string> {
               double value = 0;
               auto wrong = CheckNumber(flag, text, check, &value);
               if (!wrong) store(value);
               return wrong;
             });
  declared_.back().rule = NumberRule(check);
  if (default_value) declared_.back().default_text = NumberText(*default_value);
  return option;
}

CLI::Option* CommandLine::Number(const std::string& flag, double* into, std::string value_name,
                                 std::string help, NumberCheck check) {
  return NumberOption(
      flag, std::move(value_name), std::move(help), check, [into](double v) { *into = v; }, *into);
}

CLI::Option* CommandLine::Number(const std::string& flag, std::optional<double>* into,
                                 std::string value_name, std::string help, NumberCheck check) {
  return NumberOption(
      flag, std::move(value_name), std::move(help), check, [into](double v) { *into = v; }, *into);
}

CLI::Option* CommandLine::Whole(const std::string& flag, int* into, std::string value_name,
                                std::string help, NumberCheck check) {
  return NumberOption(
      flag, std::move(value_name), std::move(help), check.Integer(),
      [into](double v) { *into = static_cast<int>(v); }, *into);
}

CLI::Option* CommandLine::Whole(const std::string& flag, std::optional<int>* into,
                                std::string value_name, std::string help, NumberCheck check) {
  std::optional<double> default_value;
  if (*into) default_value = **into;
  return NumberOption(
      flag, std::move(value_name), std::move(help), check.Integer(),
      [into](double v) { *into = static_cast<int>(v); }, default_value);
}

CLI::Option* CommandLine::Flag(const std::string& flag, bool* into, std::string help) {
  Declared& d = Declare(flag, "", std::move(help));
  d.option = app_.add_flag(flag, *into);
  flags_.push_back(flag);
  return d.option;
}

void CommandLine::Require(const std::string& flag) {
  for (auto& d : declared_)
    if (!d.positional && d.flag == flag) d.required = true;
}

bool CommandLine::Given(const std::string& flag) const {
  const Declared* d = Find(flag);
  return d != nullptr && d->option->count() > 0;
}

std::optional<std::string> CommandLine::CheckForms() {
  // The forms every option given belongs to; the first of them is the one chosen.
  uint32_t forms = kEveryForm;
  const Declared* chooser = nullptr;  // the first option given that narrowed the forms
  for (const auto& d : declared_) {
    if (d.positional || d.option->count() == 0 || d.forms == kEveryForm) continue;
    if ((forms & d.forms) == 0) {
      std::string why;
      for (size_t f = 0; f < form_why_apart_.size(); ++f)
        if (((d.forms | chooser->forms) >> f & 1u) && !form_why_apart_[f].empty())
          why = ": " + form_why_apart_[f];
      return chooser->flag + " and " + d.flag + " do not go together" + why + " (see --help)";
    }
    if (!chooser) chooser = &d;
    forms &= d.forms;
  }
  chosen_form_ = std::countr_zero(forms);
  const uint32_t chosen = 1u << chosen_form_;
  for (const auto& d : declared_) {
    if (d.positional || !d.required || d.option->count() > 0 || !(d.forms & chosen)) continue;
    return "missing " + d.flag + " " + d.value_name + " (see --help)";
  }
  const Declared* words = nullptr;
  for (const auto& d : declared_)
    if (d.positional && (d.forms & chosen)) words = &d;
  const std::string with = chooser && chosen_form_ > 0 ? " with " + chooser->flag : "";
  if (!words) {
    if (positionals_.empty()) return std::nullopt;
    return name_ + " takes no '" + positionals_.front() + "'" + with + " (see --help)";
  }
  const size_t n = positionals_.size();
  if (n < words->at_least || n > words->at_most) {
    const std::string how = words->at_least == words->at_most
                                ? "exactly " + std::to_string(words->at_least)
                            : n < words->at_least ? "at least " + std::to_string(words->at_least)
                                                  : "at most " + std::to_string(words->at_most);
    return name_ + " takes " + how + " " + words->value_name + with + ", not " + std::to_string(n) +
           " (see --help)";
  }
  *words->positionals_into = positionals_;
  return std::nullopt;
}

std::optional<int> CommandLine::Parse(const std::vector<std::string>& argv) {
  for (const auto& a : argv) {
    if (a == "--") break;
    if (a == "--help" || a == "-h") {
      std::cout << Help();
      return 0;
    }
    // CLI11 reads a flag given a value ("--json=1") as set; monocle's flags take none.
    const auto eq = a.find('=');
    if (eq != std::string::npos &&
        std::find(flags_.begin(), flags_.end(), a.substr(0, eq)) != flags_.end()) {
      std::cerr << "monocle: error: " << a.substr(0, eq) << " takes no value\n";
      return 2;
    }
  }
  std::optional<std::string> wrong;
  try {
    // CLI11 takes a vector argument list last-first.
    app_.parse(std::vector<std::string>(argv.rbegin(), argv.rend()));
  } catch (const CLI::ArgumentMismatch& e) {
    const std::string what = e.what();
    wrong = what.substr(0, what.find(':')) + " needs a value";
  } catch (const CLI::ValidationError& e) {
    // Ours: "FLAG: message"; the message names the option itself or follows its name.
    const std::string what = e.what();
    const auto colon = what.find(": ");
    const std::string flag = what.substr(0, colon), message = what.substr(colon + 2);
    wrong = message.starts_with(flag) ? message : flag + " " + message;
  } catch (const CLI::ParseError& e) {
    wrong = std::string(e.what()) + " (see --help)";
  }
  if (!wrong) {
    for (const auto& extra : app_.remaining()) {
      if (extra == "--") continue;
      wrong = "unknown option " + extra.substr(0, extra.find('=')) + " (see --help)";
      break;
    }
  }
  if (!wrong) wrong = CheckForms();
  if (!wrong) return std::nullopt;
  std::cerr << "monocle: error: " << *wrong << "\n";
  return 2;
}

std::string CommandLine::Synopsis(int form) const {
  std::vector<std::string> parts;
  auto in_form = [&](const Declared& d) { return (d.forms >> form) & 1u; };
  for (const auto& d : declared_)
    if (d.positional && in_form(d)) parts.push_back(d.value_name + "...");
  for (const auto& d : declared_)
    if (!d.positional && d.required && in_form(d)) parts.push_back(d.flag + " " + d.value_name);
  for (const auto& d : declared_) {
    if (d.positional || d.required || !in_form(d)) continue;
    const std::string word = d.value_name.empty() ? d.flag : d.flag + " " + d.value_name;
    parts.push_back("[" + word + "]" + (d.repeatable ? "..." : ""));
  }
  // A positional taking exactly one word is shown without the dots.
  for (const auto& d : declared_)
    if (d.positional && in_form(d) && d.at_most == 1)
      for (auto& p : parts)
        if (p == d.value_name + "...") p = d.value_name;
  const std::string head = "monocle " + name_;
  // Wrapped between parts, never inside one ("[--domain D]" stays whole).
  const size_t indent = 7 + head.size() + 1;
  std::string out = head;
  size_t column = 7 + head.size();
  for (const auto& part : parts) {
    if (column + 1 + part.size() > kHelpWidth && column > indent) {
      out += "\n" + std::string(indent, ' ') + part;
      column = indent + part.size();
    } else {
      out += " " + part;
      column += 1 + part.size();
    }
  }
  return out;
}

std::string CommandLine::OptionLines(int form) const {
  std::ostringstream out;
  // Positionals first, then the options in the order they were declared.
  for (const bool positional : {true, false}) {
    for (const auto& d : declared_) {
      if (d.positional != positional || std::countr_zero(d.forms) != form) continue;
      std::string label = "  " + (d.positional ? d.value_name : d.flag);
      if (!d.positional && !d.value_name.empty()) label += " " + d.value_name;
      std::vector<std::string> details;
      if (!d.rule.empty()) details.push_back(d.rule);
      if (d.repeatable) details.push_back("repeatable");
      if (d.required) {
        details.push_back("required");
      } else if (!d.default_text.empty()) {
        details.push_back("default " + d.default_text);
      }
      const std::string help = d.help + (details.empty() ? "" : " (" + Joined(details, "; ") + ")");
      if (label.size() + 1 > kLabelWidth + 2) {
        out << label << "\n" << std::string(kLabelWidth + 2, ' ');
      } else {
        out << label << std::string(kLabelWidth + 2 - label.size(), ' ');
      }
      out << WrapText(help, kLabelWidth + 2, kLabelWidth + 2, kHelpWidth) << "\n";
    }
  }
  return out.str();
}

std::string CommandLine::Help() const {
  std::ostringstream out;
  for (size_t f = 0; f < form_headings_.size(); ++f)
    out << (f == 0 ? "Usage: " : "       ") << Synopsis(static_cast<int>(f)) << "\n";
  out << "\n" << about_;
  if (!about_.empty() && about_.back() != '\n') out << "\n";
  out << "\n" << OptionLines(0);
  for (size_t f = 1; f < form_headings_.size(); ++f)
    out << "\n" << form_headings_[f] << ":\n" << OptionLines(static_cast<int>(f));
  if (!footer_.empty()) out << "\n" << footer_ << (footer_.back() == '\n' ? "" : "\n");
  return out.str();
}

}  // namespace monocle::cli
