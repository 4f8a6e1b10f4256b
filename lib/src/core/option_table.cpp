#include "visimp/core/option_table.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "visimp/core/errors.h"

namespace visimp {

double parse_double(std::string_view text, const std::string& what) {
  double v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || std::isnan(v))
    throw UsageError(what + ": expected a number, got '" + std::string(text) + "'");
  return v;
}

std::size_t parse_count(std::string_view text, const std::string& what) {
  std::size_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw UsageError(what + ": expected a non-negative integer, got '" + std::string(text) + "'");
  return v;
}

int parse_int(std::string_view text, const std::string& what) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw UsageError(what + ": expected an integer, got '" + std::string(text) + "'");
  return v;
}

namespace {
std::string to_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

OptionSpec option_spec(std::string flag, std::string value_name, std::size_t& field, std::string help) {
  std::string what = flag;
  return {std::move(flag),
          std::move(value_name),
          std::move(help),
          std::to_string(field),
          [&field, what](std::string_view t) { field = parse_count(t, what); },
          {},
          &field,
          OptionKind::count};
}

OptionSpec option_spec(std::string flag, std::string value_name, int& field, std::string help) {
  std::string what = flag;
  return {std::move(flag),
          std::move(value_name),
          std::move(help),
          std::to_string(field),
          [&field, what](std::string_view t) { field = parse_int(t, what); },
          {},
          &field,
          OptionKind::integer};
}

OptionSpec option_spec(std::string flag, std::string value_name, double& field, std::string help) {
  std::string what = flag;
  return {std::move(flag),
          std::move(value_name),
          std::move(help),
          to_text(field),
          [&field, what](std::string_view t) { field = parse_double(t, what); },
          {},
          &field,
          OptionKind::number};
}

OptionSpec option_spec(std::string flag, std::string value_name, std::string& field, std::string help) {
  return {std::move(flag),
          std::move(value_name),
          std::move(help),
          field,
          [&field](std::string_view t) { field = std::string(t); },
          {},
          &field,
          OptionKind::text};
}

OptionSpec switch_spec(std::string flag, bool& field, std::string help) {
  return {std::move(flag), "", std::move(help), field ? "on" : "off", [&field](std::string_view) { field = true; }, {},
          &field, OptionKind::toggle};
}

OptionSpec negated_switch_spec(std::string flag, bool& field, std::string help) {
  return {std::move(flag), "", std::move(help), field ? "on" : "off", [&field](std::string_view) { field = false; }, {},
          &field, OptionKind::negated_toggle};
}

}  // namespace visimp
