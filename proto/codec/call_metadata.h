// What the server and the client agree on around a call's messages: the metadata key of the
// request id, and the canonical names of status codes (in errors and in metrics).
#pragma once

#include <grpcpp/support/status.h>

namespace isocorr::api {

// Every isocorr.v1 response carries the server's id for the call under this key, in both
// its initial and trailing metadata, so that it reaches the client whatever way the call ends.
inline constexpr const char* kRequestIdKey = "x-request-id";

const char* status_code_name(grpc::StatusCode code);  // "NOT_FOUND"

}  // namespace isocorr::api
