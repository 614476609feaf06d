// What every API method does around its body: check the bearer token, give the call a
// request id for the logs and the client (metadata "x-request-id"), turn domain errors into
// gRPC status codes, and count the call by method and code (isocorr_rpcs_total).
#pragma once

#include <functional>
#include <string>

#include <grpcpp/server_context.h>

#include "api/auth.h"

namespace isocorr::server {

struct CallInfo {
  std::string request_id;  // "r17", on every log line of the call
};

// Runs `body` when the token is valid. ServiceError kinds map to INVALID_ARGUMENT,
// NOT_FOUND, RESOURCE_EXHAUSTED, FAILED_PRECONDITION and UNAVAILABLE; InputError to
// INVALID_ARGUMENT; anything else to INTERNAL (logged). Every error leaves with its message
// escaped and its details (error_details.h).
grpc::Status guarded_call(const char* method, grpc::ServerContext& context, const TokenAuth& auth,
                          const std::function<grpc::Status(const CallInfo&)>& body);

}  // namespace isocorr::server
