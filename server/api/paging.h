// AIP-158 pagination over an ordered list: the page token is the index of the next item.
// A page ends at page_size items or kMaxPageBytes, whichever comes first, so that no list
// response can outgrow the client's message limit.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

#include "api/error_details.h"
#include "api/request_limits.h"

namespace isocorr::server {

// Appends `make(i)` for items i = token's index, ... of `count` to `items` (a repeated
// message field) while the page has room; returns the next page token, empty on the last page.
template <typename RepeatedField, typename MakeItem>
std::string fill_page(RepeatedField& items, size_t count, int page_size, const std::string& token, MakeItem make) {
  constexpr int kDefaultPageSize = 100, kMaxPageSize = 1000;
  constexpr size_t kFieldOverhead = 8;  // tag and length prefix of each item
  if (page_size < 0) throw field_error("page_size", "INVALID_PAGE_SIZE", "page_size must not be negative");
  const size_t size = page_size == 0 ? kDefaultPageSize : std::min(page_size, kMaxPageSize);
  const size_t begin = std::min(parse_page_token(token), count);
  size_t next = begin, bytes = 0;
  for (; next < count && next - begin < size; ++next) {
    auto item = make(next);
    const size_t item_bytes = item.ByteSizeLong() + kFieldOverhead;
    if (next > begin && bytes + item_bytes > kMaxPageBytes) break;  // one item always fits: its strings are bounded
    bytes += item_bytes;
    *items.Add() = std::move(item);
  }
  return next < count ? std::to_string(next) : std::string();
}

}  // namespace isocorr::server
