#include "api/request_limits.h"

#include "service_error.h"

namespace isocorr::server {
namespace {

constexpr size_t kQuotedPrefixBytes = 40;

[[noreturn]] void invalid(const std::string& message) {
  throw ServiceError(ServiceError::Kind::kInvalidArgument, message);
}

}  // namespace

std::string quoted_prefix(std::string_view value) {
  if (value.size() <= kQuotedPrefixBytes) return "'" + std::string(value) + "'";
  return "'" + std::string(value.substr(0, kQuotedPrefixBytes)) + "...' (" + std::to_string(value.size()) +
         " bytes)";
}

void require_bounded(const char* field, std::string_view value, size_t max_bytes) {
  if (value.size() > max_bytes)
    invalid(std::string(field) + " is " + std::to_string(value.size()) + " bytes long; at most " +
            std::to_string(max_bytes) + " are accepted");
  for (const char c : value)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      invalid(std::string(field) + " " + quoted_prefix(value) + " holds a control character");
}

size_t parse_page_token(const std::string& token) {
  if (token.empty()) return 0;
  require_bounded("page_token", token, kMaxPageTokenBytes);
  const bool canonical = token.find_first_not_of("0123456789") == std::string::npos &&
                         (token.size() == 1 || token[0] != '0') && token.size() < 20;  // fits in 64 bits
  if (!canonical) invalid("invalid page_token " + quoted_prefix(token) + "; pass next_page_token as it came");
  return static_cast<size_t>(std::stoull(token));
}

void require_upload_size(int64_t size_bytes) {
  if (size_bytes <= 0)
    invalid("the upload header's size_bytes must be the file's size in bytes (> 0), got " +
            std::to_string(size_bytes));
}

}  // namespace isocorr::server
