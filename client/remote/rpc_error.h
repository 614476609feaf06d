// Failed calls and what the user sees of them: a message, a JSON error object for
// --json, and an exit code that tells bad input, no server, no token and failure apart.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <grpcpp/client_context.h>
#include <grpcpp/support/status.h>

namespace isocorr::cli {

// The google.rpc.Status details of a failed call that the CLI shows.
struct ErrorDetails {
  std::string reason;  // ErrorInfo.reason, "" without one
  std::vector<std::pair<std::string, std::string>> field_violations;  // BadRequest: field, description
};
ErrorDetails error_details_of(const grpc::Status& status);

class RpcError : public std::runtime_error {
 public:
  // `request_id`: the server's id for the failed call, when it answered with one; the
  // message then ends with "(request <id>)" so that a user can quote it. With BadRequest
  // details the message is "<what>: <field>: <description>" for each field instead.
  RpcError(const std::string& what, const grpc::Status& status, const std::string& request_id = "");
  const grpc::Status& status() const { return status_; }
  const std::string& request_id() const { return request_id_; }
  const ErrorDetails& details() const { return details_; }

 private:
  RpcError(const std::string& what, const grpc::Status& status, const std::string& request_id, ErrorDetails details);

  grpc::Status status_;
  std::string request_id_;
  ErrorDetails details_;
};

// The server's request id for a finished call ("" when it sent none, e.g. health checks or
// a server that never answered).
std::string request_id_of(const grpc::ClientContext& context);

// Logs the call's request id (with --verbose) and throws RpcError("<what>: <server's
// message> (request <id>)") unless `status` is OK.
void check_rpc(const grpc::Status& status, const grpc::ClientContext& context, const std::string& what);

int exit_code_for(grpc::StatusCode code);

// Runs a remote command: RpcError and InputError become a message on stderr (a JSON
// object on stdout with `json`) and the matching exit code.
int run_remote_command(bool json, const std::function<int()>& body);

}  // namespace isocorr::cli
