// Failed calls and what the user sees of them: a message, a JSON error object for
// --json, and an exit code that tells bad input, no server, no token and failure apart.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include <grpcpp/support/status.h>

namespace isocorr::cli {

class RpcError : public std::runtime_error {
 public:
  RpcError(const std::string& what, const grpc::Status& status);
  const grpc::Status& status() const { return status_; }

 private:
  grpc::Status status_;
};

// Throws RpcError("<what>: <server's message>") unless `status` is OK.
void check_rpc(const grpc::Status& status, const std::string& what);

const char* status_code_name(grpc::StatusCode code);
int exit_code_for(grpc::StatusCode code);

// Runs a remote command: RpcError and InputError become a message on stderr (a JSON
// object on stdout with `json`) and the matching exit code.
int run_remote_command(bool json, const std::function<int()>& body);

}  // namespace isocorr::cli
