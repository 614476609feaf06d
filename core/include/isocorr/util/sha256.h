// Incremental SHA-256 (OpenSSL): the name of every stored mesh, computed by the server on
// upload and by the client before it uploads.
#pragma once

#include <memory>
#include <string>
#include <string_view>

namespace isocorr {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(std::string_view bytes);
  // Lower-case hex of the digest; the hasher cannot be updated afterwards.
  std::string hex_digest();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The lower-case hex digest of `bytes` in one call.
std::string sha256_hex(std::string_view bytes);

// True for 64 lower-case hex characters.
bool is_sha256_hex(std::string_view text);

}  // namespace isocorr
