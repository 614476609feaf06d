#include "codec/result_part_codec.h"

namespace isocorr::api {

std::optional<ResultPart> result_part_from_proto(int value) {
  if (value < 1 || value > static_cast<int>(kAllResultParts.size())) return std::nullopt;
  return kAllResultParts[value - 1];
}

v1::ResultPart result_part_to_proto(ResultPart part) {
  return static_cast<v1::ResultPart>(static_cast<int>(part) + 1);
}

}  // namespace isocorr::api
