// One command's command line, declared once. Each option is declared with its typed field,
// its value's name, unit, default and check; CLI11 parses the words into the fields and runs
// the checks, and `--help` (and so the reference page, client/cli/README.md) is generated from
// the same declarations. Errors are in monocle's words and name the option; the caller exits
// with status 2 on them.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "service/common/result.h"

namespace monocle::cli {

// What a number may be; the help and the error message both say it. Written as
// In("pixels").AtLeast(0), In("degrees").Between(0.01, 5), In("seconds").Above(0).
struct NumberCheck {
  std::string unit;  // plural, e.g. "pixels", "metres", "seconds"
  std::optional<double> min, max;
  bool above_min = false;  // min itself not allowed (> instead of >=)
  bool whole = false;      // a whole number

  NumberCheck AtLeast(double v) const { return With(v, max, false, whole); }
  NumberCheck Above(double v) const { return With(v, max, true, whole); }
  NumberCheck Between(double lo, double hi) const { return With(lo, hi, false, whole); }
  NumberCheck Integer() const { return With(min, max, above_min, true); }

 private:
  NumberCheck With(std::optional<double> lo, std::optional<double> hi, bool above,
                   bool integer) const {
    NumberCheck c = *this;
    c.min = lo;
    c.max = hi;
    c.above_min = above;
    c.whole = integer;
    return c;
  }
};
inline NumberCheck In(std::string unit) {
  NumberCheck c;
  c.unit = std::move(unit);
  return c;
}

class CommandLine {
 public:
  // `name`: the command's words ("floor calibrate"); `about`: what it does, printed after the
  // usage (paragraphs, already wrapped).
  CommandLine(std::string name, std::string about);

  // Starts another form of the command (e.g. "live, from the running service") and returns
  // its number (the first form, before any Form call, is 0): options and positionals
  // declared from now on belong to it only, and are listed under `heading`. Those declared
  // before the first Form belong to every form. The options given choose the form; options
  // with no form in common are an error.
  // `why_apart`, if given, ends the error for options of this form given with others.
  int Form(std::string heading, std::string why_apart = "");
  // Options declared from now on belong to these forms (listed with the first of them).
  void InForms(std::initializer_list<int> forms);
  // ... or to every form.
  void Shared() { declaring_forms_ = kEveryForm; }
  // Printed at the end of the help.
  void Footer(std::string text) { footer_ = std::move(text); }

  // Positional words, in order. `at_least`/`at_most` bound how many the chosen form takes.
  void Positionals(std::string value_name, std::vector<std::string>* into, std::string help,
                   size_t at_least = 1, size_t at_most = SIZE_MAX);

  // --flag VALUE: the text as given (a path, an id). Absent: `into` is left as it is.
  CLI::Option* Text(const std::string& flag, std::string* into, std::string value_name,
                    std::string help);
  CLI::Option* Text(const std::string& flag, std::optional<std::string>* into,
                    std::string value_name, std::string help);
  // Repeatable: --flag VALUE --flag VALUE ...
  CLI::Option* Texts(const std::string& flag, std::vector<std::string>* into,
                     std::string value_name, std::string help);
  // One of `choices`.
  CLI::Option* Choice(const std::string& flag, std::string* into, std::vector<std::string> choices,
                      std::string help);
  // A number; its current value is the default the help shows, unless `required`.
  CLI::Option* Number(const std::string& flag, double* into, std::string value_name,
                      std::string help, NumberCheck check);
  CLI::Option* Number(const std::string& flag, std::optional<double>* into, std::string value_name,
                      std::string help, NumberCheck check);
  CLI::Option* Whole(const std::string& flag, int* into, std::string value_name, std::string help,
                     NumberCheck check);
  CLI::Option* Whole(const std::string& flag, std::optional<int>* into, std::string value_name,
                     std::string help, NumberCheck check);
  // A value with a format of its own (X,Y,HEADING_DEG, COLSxROWS, ...): `parse` turns the
  // text into the value or says what is wrong with it (the message follows the option's name).
  template <typename T>
  CLI::Option* Parsed(const std::string& flag, std::optional<T>* into, std::string value_name,
                      std::string help, std::function<Result<T>(const std::string&)> parse) {
    return Custom(flag, std::move(value_name), std::move(help),
                  [into, parse](const std::string& text) -> std::optional<std::string> {
                    auto value = parse(text);
                    if (!value) return value.error().message;
                    *into = std::move(*value);
                    return std::nullopt;
                  });
  }
  // The general form: `assign` takes the text, stores what it means and returns empty, or
  // returns what is wrong with it.
  CLI::Option* Custom(const std::string& flag, std::string value_name, std::string help,
                      std::function<std::optional<std::string>(const std::string&)> assign);
  // Repeatable: `assign` takes each occurrence's text in turn.
  CLI::Option* CustomRepeated(const std::string& flag, std::string value_name, std::string help,
                              std::function<std::optional<std::string>(const std::string&)> assign);
  // --flag, no value.
  CLI::Option* Flag(const std::string& flag, bool* into, std::string help);

  // Marks a declared option as required in its form(s).
  void Require(const std::string& flag);

  // Parses `argv` into the declared fields. Empty: go on; else the exit status to return now
  // (0 after printing --help, 2 after printing what is wrong with the command line).
  std::optional<int> Parse(const std::vector<std::string>& argv);
  bool Given(const std::string& flag) const;
  // The form chosen by the options given: 0 is the first.
  int ChosenForm() const { return chosen_form_; }
  std::string Help() const;

 private:
  struct Declared {
    std::string flag;  // "--board", or a positional's value name
    std::string value_name;
    std::string help;
    std::string rule;             // what a value must be, e.g. "a number of pixels >= 0"
    std::string default_text;     // shown unless required
    uint32_t forms = kEveryForm;  // bit f: belongs to form f
    bool required = false;
    bool positional = false;
    bool repeatable = false;
    size_t at_least = 0, at_most = SIZE_MAX;
    std::vector<std::string>* positionals_into = nullptr;
    CLI::Option* option = nullptr;
  };
  Declared& Declare(const std::string& flag, std::string value_name, std::string help);
  CLI::Option* NumberOption(const std::string& flag, std::string value_name, std::string help,
                            NumberCheck check, std::function<void(double)> store,
                            std::optional<double> default_value);
  const Declared* Find(const std::string& flag) const;
  std::optional<std::string> CheckForms();
  std::string Synopsis(int form) const;
  // The options listed under form `form`: those whose first form it is.
  std::string OptionLines(int form) const;

  std::string name_, about_, footer_;
  static constexpr uint32_t kEveryForm = ~0u;
  std::vector<std::string> form_headings_{""};
  std::vector<std::string> form_why_apart_{""};
  uint32_t declaring_forms_ = kEveryForm;
  std::vector<Declared> declared_;
  std::vector<std::string> positionals_;  // every positional word, in order
  std::vector<std::string> flags_;        // the declared flags (no value)
  int chosen_form_ = 0;
  CLI::App app_;
};

// The words of `text` wrapped to `width` columns, the first line starting at `first_column`
// and the others indented by `indent`.
std::string WrapText(const std::string& text, size_t first_column, size_t indent, size_t width);

// Text for a number in help and messages: 0.5, 30, 1e-06.
std::string NumberText(double value);

}  // namespace monocle::cli
