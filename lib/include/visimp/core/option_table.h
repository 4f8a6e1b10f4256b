// Binds command-line flags to the fields of an options struct, so the apps' --help text,
// defaults and parsing come from the library's structs and cannot drift apart.
//
//   SimplifyOptions o;
//   for (const OptionSpec& s : describe_options(o)) ...   // s.flag, s.help, s.default_text
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "visimp/core/errors.h"

namespace visimp {

/// What a spec's `target` points to, so a summary can read the value in force with its type.
enum class OptionKind {
  count,    ///< std::size_t
  integer,  ///< int
  number,   ///< double
  text,     ///< std::string
  choice,   ///< an enum, named by one of the spec's choices (default_text when the spec was made)
  toggle,          ///< bool, set by the flag ("--no-folds": prevent_folds)
  negated_toggle,  ///< bool, cleared by the flag ("--no-refine": refine)
};

struct OptionSpec {
  std::string flag;                           ///< "--max-error"
  std::string value_name;                     ///< "E"; empty for a switch that takes no value
  std::string help;                           ///< meaning, unit and range
  std::string default_text;                   ///< the field's value when the spec was made
  std::function<void(std::string_view)> set;  ///< parses a value into the field; throws UsageError
  /// Non-empty: the value may be left out ("--drop-hidden" means "--drop-hidden 0"); a value
  /// is then taken only as "--flag=V" or when the next argument is a number.
  std::string implicit_value;
  /// The bound field: an OptionError about it (core/errors.h) is reported with this flag.
  const void* target = nullptr;
  OptionKind kind = OptionKind::text;
};

OptionSpec option_spec(std::string flag, std::string value_name, std::size_t& field, std::string help);
OptionSpec option_spec(std::string flag, std::string value_name, int& field, std::string help);
OptionSpec option_spec(std::string flag, std::string value_name, double& field, std::string help);
OptionSpec option_spec(std::string flag, std::string value_name, std::string& field, std::string help);
/// One of a fixed set of names ("--quadric-weights area"); anything else is a UsageError
/// listing the names. `choices` pairs each name with its value; the help should name them.
template <class Enum>
OptionSpec choice_spec(std::string flag, std::string value_name, Enum& field,
                       std::vector<std::pair<std::string, Enum>> choices, std::string help);
/// A switch: present means true.
OptionSpec switch_spec(std::string flag, bool& field, std::string help);
/// A switch that turns a default-on feature off ("--no-refine"); its default text is the feature's state.
OptionSpec negated_switch_spec(std::string flag, bool& field, std::string help);

/// Parsers shared by the specs and the apps; they throw UsageError naming `what`.
double parse_double(std::string_view text, const std::string& what);
std::size_t parse_count(std::string_view text, const std::string& what);
int parse_int(std::string_view text, const std::string& what);

template <class Enum>
OptionSpec choice_spec(std::string flag, std::string value_name, Enum& field,
                       std::vector<std::pair<std::string, Enum>> choices, std::string help) {
  std::string names, current;
  for (const auto& [name, value] : choices) {
    names += (names.empty() ? "" : "|") + name;
    if (value == field) current = name;
  }
  auto set = [&field, choices, names, flag](std::string_view text) {
    for (const auto& [name, value] : choices)
      if (text == name) {
        field = value;
        return;
      }
    throw UsageError(flag + " must be one of " + names + ", not '" + std::string(text) + "'");
  };
  return {std::move(flag), std::move(value_name), std::move(help), current, std::move(set), {}, &field,
          OptionKind::choice};
}

}  // namespace visimp
