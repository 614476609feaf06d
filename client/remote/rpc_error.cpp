#include "remote/rpc_error.h"

#include <cstdio>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "codec/call_metadata.h"
#include "commands.h"
#include "isocorr/util/error.h"

namespace isocorr::cli {

RpcError::RpcError(const std::string& what, const grpc::Status& status, const std::string& request_id)
    : std::runtime_error(what + ": " + status.error_message() +
                         (request_id.empty() ? "" : " (request " + request_id + ")")),
      status_(status),
      request_id_(request_id) {}

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
  auto report = [&](const char* code, const std::string& message, const std::string& request_id = "") {
    if (json) {
      nlohmann::json error{{"code", code}, {"message", message}};
      if (!request_id.empty()) error["request_id"] = request_id;
      std::printf("%s\n", nlohmann::json{{"error", error}}.dump().c_str());
    }
    spdlog::error("{}", message);
  };
  try {
    return body();
  } catch (const RpcError& e) {
    report(api::status_code_name(e.status().error_code()), e.what(), e.request_id());
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
