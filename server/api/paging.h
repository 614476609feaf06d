// AIP-158 pagination over an ordered list: the page token is the index of the next item.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

#include "service_error.h"

namespace isocorr::server {

struct Page {
  size_t begin = 0, end = 0;
  std::string next_token;  // empty on the last page
};

inline Page page_of(size_t count, int page_size, const std::string& token) {
  constexpr int kDefaultPageSize = 100, kMaxPageSize = 1000;
  if (page_size < 0) throw ServiceError(ServiceError::Kind::kInvalidArgument, "page_size must not be negative");
  const size_t size = page_size == 0 ? kDefaultPageSize : std::min(page_size, kMaxPageSize);
  Page page;
  if (!token.empty()) {
    try {
      page.begin = std::stoul(token);
    } catch (const std::exception&) {
      throw ServiceError(ServiceError::Kind::kInvalidArgument, "invalid page_token '" + token + "'");
    }
  }
  page.begin = std::min(page.begin, count);
  page.end = std::min(count, page.begin + size);
  if (page.end < count) page.next_token = std::to_string(page.end);
  return page;
}

}  // namespace isocorr::server
