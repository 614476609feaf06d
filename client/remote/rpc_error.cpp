#include "remote/rpc_error.h"

#include <cstdio>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "codec/call_metadata.h"
#include "commands.h"
#include "google/rpc/error_details.pb.h"
#include "google/rpc/status.pb.h"
#include "isocorr/util/error.h"

namespace isocorr::cli {
namespace {

// The server's message, or what its BadRequest says of each field when it sent one.
std::string explanation(const grpc::Status& status, const ErrorDetails& details) {
  if (details.field_violations.empty()) return status.error_message();
  std::string text;
  for (const auto& [field, description] : details.field_violations)
    text.append(text.empty() ? "" : "; ").append(field).append(": ").append(description);
  return text;
}

}  // namespace

ErrorDetails error_details_of(const grpc::Status& status) {
  ErrorDetails details;
  google::rpc::Status proto;
  if (status.error_details().empty() || !proto.ParseFromString(status.error_details())) return details;
  for (const auto& any : proto.details()) {
    google::rpc::ErrorInfo info;
    google::rpc::BadRequest bad_request;
    if (any.UnpackTo(&info)) {
      details.reason = info.reason();
    } else if (any.UnpackTo(&bad_request)) {
      for (const auto& violation : bad_request.field_violations())
        details.field_violations.emplace_back(violation.field(), violation.description());
    }
  }
  return details;
}

RpcError::RpcError(const std::string& what, const grpc::Status& status, const std::string& request_id)
    : RpcError(what, status, request_id, error_details_of(status)) {}

RpcError::RpcError(const std::string& what, const grpc::Status& status, const std::string& request_id,
                   ErrorDetails details)
    : std::runtime_error(what + ": " + explanation(status, details) +
                         (request_id.empty() ? "" : " (request " + request_id + ")")),
      status_(status),
      request_id_(request_id),
      details_(std::move(details)) {}

std::string request_id_of(const grpc::ClientContext& context) {
  // Trailing first: a call that failed before any response header carries it only there.
  for (const auto* metadata : {&context.GetServerTrailingMetadata(), &context.GetServerInitialMetadata()})
    if (auto it = metadata->find(api::kRequestIdKey); it != metadata->end())
      return std::string(it->second.data(), it->second.size());
  return "";
}

void check_rpc(const grpc::Status& status, const grpc::ClientContext& context, const std::string& what) {
  const std::string request_id = request_id_of(context);
  if (!request_id.empty()) spdlog::debug("server request {}: {}", request_id, api::status_code_name(status.error_code()));
  if (!status.ok()) throw RpcError(what, status, request_id);
}

int exit_code_for(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::OUT_OF_RANGE:
      return kExitBadInput;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::CANCELLED:  // the client cancels no call it reports: the server ended it
      return kExitUnavailable;
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::PERMISSION_DENIED:
      return kExitUnauthenticated;
    default:
      return kExitFailure;
  }
}

int run_remote_command(bool json, const std::function<int()>& body) {
  auto report = [&](const char* code, const std::string& message, const std::string& request_id = "",
                    const ErrorDetails& details = {}) {
    if (json) {
      nlohmann::json error{{"code", code}, {"message", message}};
      if (!request_id.empty()) error["request_id"] = request_id;
      if (!details.reason.empty()) error["reason"] = details.reason;
      for (const auto& [field, description] : details.field_violations)
        error["field_violations"].push_back({{"field", field}, {"description", description}});
      std::printf("%s\n", nlohmann::json{{"error", error}}.dump().c_str());
    }
    spdlog::error("{}", message);
  };
  try {
    return body();
  } catch (const RpcError& e) {
    report(api::status_code_name(e.status().error_code()), e.what(), e.request_id(), e.details());
    return exit_code_for(e.status().error_code());
  } catch (const InputError& e) {
    report("INVALID_ARGUMENT", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    report("INTERNAL", e.what());
    return kExitFailure;
  }
}

}  // namespace isocorr::cli
