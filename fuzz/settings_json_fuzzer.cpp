// Match settings read back from JSON (a job record's "settings"): any JSON value.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "isocorr/settings/settings_json.h"
#include "isocorr/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  try {
    isocorr::settings_from_json(json);
  } catch (const isocorr::InputError&) {
  }
  return 0;
}
