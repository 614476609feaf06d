// JSON documents of the data directory that carry their own SHA-256, so that any changed
// byte is noticed when they are read back: {"sha256": <digest of the compact body>, "body": ...}.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace isocorr::server {

std::string seal_json(const nlohmann::json& body);

// The body; throws std::runtime_error when the text does not parse or the digest does not
// match. A document without the seal (written before seals existed) is returned as it is.
nlohmann::json unseal_json(const std::string& text);

}  // namespace isocorr::server
