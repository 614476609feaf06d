// Tokenising and message helpers the text readers share: whitespace tokens and comment-free
// lines as views into the file's bytes, strict number parsing, and short quotes of file
// bytes for messages.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

#include "isocorr/util/error.h"

namespace isocorr::mesh_formats {

using std::string_view;

template <class... Parts>
std::string cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

[[noreturn]] inline void fail(string_view format, const std::string& message) {
  throw InputError(cat(format, ": ", message));
}

// File bytes echoed in messages: printable, and short even for binary garbage.
inline std::string shown(string_view token) {
  std::string out = "'";
  for (char c : token.substr(0, 24)) out += (c >= 32 && c < 127) ? c : '?';
  return out + (token.size() > 24 ? "...'" : "'");
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// Splits text at whitespace; tokens are views into the file's bytes.
class Tokens {
 public:
  explicit Tokens(string_view text) : rest_(text) {}
  bool next(string_view& token) {
    size_t begin = 0;
    while (begin < rest_.size() && is_space(rest_[begin])) ++begin;
    size_t end = begin;
    while (end < rest_.size() && !is_space(rest_[end])) ++end;
    token = rest_.substr(begin, end - begin);
    rest_.remove_prefix(end);
    return !token.empty();
  }

 private:
  string_view rest_;
};

// Yields the non-blank lines of a text with '#' comments removed, counting line numbers.
class Lines {
 public:
  explicit Lines(string_view text) : rest_(text) {}
  bool next(string_view& line) {
    while (!rest_.empty()) {
      const size_t end = std::min(rest_.find('\n'), rest_.size());
      line = rest_.substr(0, end);
      rest_.remove_prefix(std::min(end + 1, rest_.size()));
      ++number_;
      line = line.substr(0, line.find('#'));
      if (std::any_of(line.begin(), line.end(), [](char c) { return !is_space(c); })) return true;
    }
    return false;
  }
  long long number() const { return number_; }
  size_t remaining() const { return rest_.size(); }

 private:
  string_view rest_;
  long long number_ = 0;
};

inline bool parse_number(string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, error] = std::from_chars(token.data(), end, value);
  if (token.empty() || ptr != end) return false;
  // Overflow and underflow still have a value (inf or 0) that the callers judge.
  if (error == std::errc::result_out_of_range) value = std::strtod(std::string(token).c_str(), nullptr);
  return error == std::errc() || error == std::errc::result_out_of_range;
}

inline bool parse_integer(string_view token, long long& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, error] = std::from_chars(token.data(), end, value);
  return !token.empty() && error == std::errc() && ptr == end;
}

// Appends `value` in the shortest text that parses back to the same double.
inline void append_exact(std::string& out, double value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, end);
}

}  // namespace isocorr::mesh_formats
