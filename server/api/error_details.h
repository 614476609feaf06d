// The details every error status of the service carries, as AIP-193 asks: a google.rpc.Status
// (gRPC's grpc-status-details-bin trailer) holding an ErrorInfo (reason, domain, metadata
// with the request id and the field to blame) and, when one request field is invalid, a
// BadRequest field violation naming it.
#pragma once

#include <string>

#include <grpcpp/support/status.h>

#include "service_error.h"

namespace isocorr::server {

inline constexpr const char* kErrorDomain = "isocorr.dev";

// A refusal the API layer can say more about: its reason (UPPER_SNAKE_CASE, stable for
// programs to test) and the request field at fault ("name", "settings.level0_samples"),
// empty when none is.
class DetailedError : public ServiceError {
 public:
  DetailedError(Kind kind, std::string reason, std::string field, const std::string& message)
      : ServiceError(kind, message), reason_(std::move(reason)), field_(std::move(field)) {}
  const std::string& reason() const { return reason_; }
  const std::string& field() const { return field_; }

 private:
  std::string reason_, field_;
};

// INVALID_ARGUMENT for one bad request field.
inline DetailedError field_error(std::string field, std::string reason, const std::string& message) {
  return DetailedError(ServiceError::Kind::kInvalidArgument, std::move(reason), std::move(field), message);
}

// `status` (an error) with its message escaped (escape_text) and, unless it has details
// already, the details above; an empty `reason` becomes the status code's name.
grpc::Status with_details(const grpc::Status& status, const std::string& reason, const std::string& field,
                          const std::string& request_id);

}  // namespace isocorr::server
