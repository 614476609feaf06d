// Bearer-token check for every call of the isocorr services ("authorization: Bearer
// <token>" metadata). gRPC's AuthMetadataProcessor works only with TLS credentials, and
// the server also runs without TLS on loopback, so the services call this themselves.
#pragma once

#include <string>

#include <grpcpp/server_context.h>

namespace isocorr::server {

class TokenAuth {
 public:
  explicit TokenAuth(std::string token) : token_(std::move(token)) {}  // empty = no auth
  bool enabled() const { return !token_.empty(); }
  // OK, or UNAUTHENTICATED saying what is missing.
  grpc::Status check(const grpc::ServerContext& context) const;

 private:
  std::string token_;
};

}  // namespace isocorr::server
