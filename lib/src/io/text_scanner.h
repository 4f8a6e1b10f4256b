// Private helper of the ASCII readers: splits a memory buffer into lines and tokens and
// parses numbers with std::from_chars, tracking the line number for error messages.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "visimp/core/errors.h"

namespace visimp::detail {

class TextScanner {
 public:
  TextScanner(std::string_view text, const std::string& name, std::size_t first_line = 1)
      : text_(text), name_(name), line_number_(first_line - 1) {}

  /// Advances to the next line; false at end of input. Strips '\r' and trailing spaces.
  bool next_line() {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line_ = text_.substr(pos_, stop - pos_);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    while (!line_.empty() && (line_.back() == '\r' || line_.back() == ' ' || line_.back() == '\t'))
      line_.remove_suffix(1);
    ++line_number_;
    return true;
  }
  std::string_view line() const { return line_; }
  std::size_t line_number() const { return line_number_; }
  std::size_t remaining_bytes() const { return text_.size() - pos_; }

  /// Splits the current line on blanks into `tokens`.
  void tokens(std::vector<std::string_view>& out) const { split(line_, out); }

  static void split(std::string_view s, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
      const std::size_t start = i;
      while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
      if (i > start) out.push_back(s.substr(start, i - start));
    }
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw IoError(name_, "line " + std::to_string(line_number_) + ": " + problem);
  }

  double to_double(std::string_view token, const char* what) const {
    double value = 0;
    const char* begin = token.data();
    if (!token.empty() && token[0] == '+') ++begin;
    const auto [ptr, ec] = std::from_chars(begin, token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size())
      fail(std::string("expected a number for ") + what + ", found '" + std::string(token.substr(0, 40)) + "'");
    return value;
  }

  std::int64_t to_int(std::string_view token, const char* what) const {
    std::int64_t value = 0;
    const char* begin = token.data();
    if (!token.empty() && token[0] == '+') ++begin;
    const auto [ptr, ec] = std::from_chars(begin, token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size())
      fail(std::string("expected an integer for ") + what + ", found '" + std::string(token.substr(0, 40)) + "'");
    return value;
  }

 private:
  std::string_view text_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::string_view line_;
  std::size_t line_number_;
};

/// Appends the fan triangulation (v0, vi, vi+1) of a polygon; the caller checks size >= 3.
template <class Faces>
void append_fan(const std::vector<std::uint32_t>& polygon, Faces& faces) {
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) faces.push_back({polygon[0], polygon[i], polygon[i + 1]});
}

}  // namespace visimp::detail
