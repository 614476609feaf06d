// Bounds on what clients send, checked at the API boundary before anything is stored or
// echoed: every string a client supplies has a maximum length, page tokens parse strictly,
// and error messages quote at most a short prefix of a bad value (a long one would not
// fit in the status trailer and reach the client as RESOURCE_EXHAUSTED instead).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace isocorr::server {

// "meshes/{sha256}" has 71 bytes and "jobs/{id}" 21: anything near this is not a name.
constexpr size_t kMaxNameBytes = 128;
// The longest file name of common file systems.
constexpr size_t kMaxFilenameBytes = 255;
// Page tokens are item indices written in decimal.
constexpr size_t kMaxPageTokenBytes = 20;
// A list page stops growing here, far below gRPC's default 4 MiB message limit.
constexpr size_t kMaxPageBytes = size_t{1} << 20;

// Client text made safe for a message or a log line: control characters (C0, DEL, C1,
// U+2028/9) become \n, \r, \t, \xNN or \uNNNN, and bytes that are not UTF-8 become \xNN.
// Backslashes stay as they are, so escaping twice changes nothing.
std::string escape_text(std::string_view text);

// `value` in quotes, escaped, cut to a short prefix with its length when long: safe in any
// message.
std::string quoted_prefix(std::string_view value);

// Throws a field_error naming `field` when `value` is longer than `max_bytes` or holds
// control characters (names and file names are shown one per line by the client).
void require_bounded(const char* field, std::string_view value, size_t max_bytes);

// The index a page token stands for: exactly the decimal the server wrote ("" = 0).
// Throws a field_error for anything else ("-1", " 5", "5abc", "1e3", "05").
size_t parse_page_token(const std::string& token);

// The upload header's size_bytes must announce a non-empty file.
void require_upload_size(int64_t size_bytes);

}  // namespace isocorr::server
