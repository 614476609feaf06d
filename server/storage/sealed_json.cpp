#include "storage/sealed_json.h"

#include <stdexcept>

#include "isocorr/util/sha256.h"

namespace isocorr::server {
namespace {

// Compact, keys sorted, invalid UTF-8 replaced: parsing it and dumping again gives the same text.
std::string canonical(const nlohmann::json& body) {
  return body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}


}  // namespace

std::string seal_json(const nlohmann::json& body) {
  const std::string text = canonical(body);
  return "{\"body\":" + text + ",\"sha256\":\"" + sha256_hex(text) + "\"}";
}

nlohmann::json unseal_json(const std::string& text) {
  nlohmann::json document = nlohmann::json::parse(text);  // throws on malformed text
  if (!document.is_object() || !document.contains("sha256")) return document;
  if (!document.contains("body") || !document["sha256"].is_string() ||
      document["sha256"].get<std::string>() != sha256_hex(canonical(document["body"])))
    throw std::runtime_error("its content does not match its sha256");
  return document["body"];
}

}  // namespace isocorr::server
