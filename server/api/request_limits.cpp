#include "api/request_limits.h"

#include <algorithm>
#include <cstdio>

#include "api/error_details.h"

namespace isocorr::server {
namespace {

constexpr size_t kQuotedPrefixBytes = 40;


// The length of the well-formed UTF-8 sequence at the start of `text` and its code point;
// 0 when it is not one (stray continuation, overlong form, surrogate, cut short).
size_t utf8_sequence(std::string_view text, char32_t& code_point) {
  const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  size_t length = 0;
  char32_t minimum = 0;
  if (lead < 0x80) length = 1, code_point = lead;
  else if (lead >= 0xc2 && lead <= 0xdf) length = 2, code_point = lead & 0x1f, minimum = 0x80;
  else if (lead >= 0xe0 && lead <= 0xef) length = 3, code_point = lead & 0x0f, minimum = 0x800;
  else if (lead >= 0xf0 && lead <= 0xf4) length = 4, code_point = lead & 0x07, minimum = 0x10000;
  else return 0;
  if (text.size() < length) return 0;
  for (size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xc0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(i) & 0x3f);
  }
  if (code_point < minimum || code_point > 0x10ffff || (code_point >= 0xd800 && code_point <= 0xdfff)) return 0;
  return length;
}

bool is_control(char32_t c) { return c < 0x20 || (c >= 0x7f && c <= 0x9f) || c == 0x2028 || c == 0x2029; }

}  // namespace

std::string escape_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  char buffer[8];
  while (!text.empty()) {
    char32_t c = 0;
    const size_t length = utf8_sequence(text, c);
    if (length == 0) {  // not UTF-8: the byte itself
      std::snprintf(buffer, sizeof buffer, "\\x%02x", static_cast<unsigned char>(text[0]));
      out += buffer;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (is_control(c)) {
      std::snprintf(buffer, sizeof buffer, c < 0x80 ? "\\x%02x" : "\\u%04x", static_cast<unsigned>(c));
      out += buffer;
    } else {
      out.append(text.substr(0, length));
    }
    text.remove_prefix(std::max<size_t>(length, 1));
  }
  return out;
}

std::string quoted_prefix(std::string_view value) {
  if (value.size() <= kQuotedPrefixBytes) return "'" + escape_text(value) + "'";
  return "'" + escape_text(value.substr(0, kQuotedPrefixBytes)) + "...' (" + std::to_string(value.size()) +
         " bytes)";
}

void require_bounded(const char* field, std::string_view value, size_t max_bytes) {
  if (value.size() > max_bytes)
    throw field_error(field, "FIELD_TOO_LONG",
                      std::string(field) + " is " + std::to_string(value.size()) + " bytes long; at most " +
                          std::to_string(max_bytes) + " are accepted");
  for (const char c : value)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw field_error(field, "CONTROL_CHARACTER",
                        std::string(field) + " " + quoted_prefix(value) + " holds a control character");
}

size_t parse_page_token(const std::string& token) {
  if (token.empty()) return 0;
  require_bounded("page_token", token, kMaxPageTokenBytes);
  const bool canonical = token.find_first_not_of("0123456789") == std::string::npos &&
                         (token.size() == 1 || token[0] != '0') && token.size() < 20;  // fits in 64 bits
  if (!canonical)
    throw field_error("page_token", "INVALID_PAGE_TOKEN",
                      "invalid page_token " + quoted_prefix(token) + "; pass next_page_token as it came");
  return static_cast<size_t>(std::stoull(token));
}

void require_upload_size(int64_t size_bytes) {
  if (size_bytes <= 0)
    throw field_error("header.size_bytes", "INVALID_UPLOAD_SIZE",
                      "the upload header's size_bytes must be the file's size in bytes (> 0), got " +
                          std::to_string(size_bytes));
}

}  // namespace isocorr::server
