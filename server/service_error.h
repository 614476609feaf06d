// Errors of the server's domain layer. The API layer turns each kind into the matching
// gRPC status code; the message is shown to the user as it is, so it says what to do.
#pragma once

#include <stdexcept>
#include <string>

namespace isocorr::server {

class ServiceError : public std::runtime_error {
 public:
  // kDataLoss: a stored object is not what was stored (it has been quarantined).
  enum class Kind { kInvalidArgument, kNotFound, kResourceExhausted, kFailedPrecondition, kUnavailable, kDataLoss };
  ServiceError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

}  // namespace isocorr::server
