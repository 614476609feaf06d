#include "api/call_guard.h"

#include <atomic>

#include <spdlog/spdlog.h>

#include "api/error_details.h"
#include "api/request_limits.h"
#include "codec/call_metadata.h"
#include "isocorr/util/error.h"
#include "metrics/server_metrics.h"
#include "service_error.h"

namespace isocorr::server {
namespace {

grpc::StatusCode code_for(ServiceError::Kind kind) {
  switch (kind) {
    case ServiceError::Kind::kInvalidArgument: return grpc::StatusCode::INVALID_ARGUMENT;
    case ServiceError::Kind::kNotFound: return grpc::StatusCode::NOT_FOUND;
    case ServiceError::Kind::kResourceExhausted: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case ServiceError::Kind::kFailedPrecondition: return grpc::StatusCode::FAILED_PRECONDITION;
    case ServiceError::Kind::kUnavailable: return grpc::StatusCode::UNAVAILABLE;
    case ServiceError::Kind::kDataLoss: return grpc::StatusCode::DATA_LOSS;
  }
  return grpc::StatusCode::INTERNAL;
}

}  // namespace

grpc::Status guarded_call(const char* method, grpc::ServerContext& context, const TokenAuth& auth,
                          const std::function<grpc::Status(const CallInfo&)>& body) {
  static std::atomic<uint64_t> counter{0};
  const CallInfo call{std::string("r").append(std::to_string(++counter))};  // not "r" + ...: GCC 12 -Wrestrict false positive
  spdlog::debug("[{}] {} from {}", call.request_id, method, context.peer());
  // Initial metadata reaches a client that reads it as soon as the call starts; the
  // trailing copy also reaches one whose call ended before any header was sent.
  context.AddInitialMetadata(api::kRequestIdKey, call.request_id);
  context.AddTrailingMetadata(api::kRequestIdKey, call.request_id);
  grpc::Status status = auth.check(context);
  std::string reason, field;  // of a DetailedError
  if (status.ok()) {
    try {
      status = body(call);
    } catch (const ServiceError& e) {
      status = grpc::Status(code_for(e.kind()), e.what());
      if (const auto* detailed = dynamic_cast<const DetailedError*>(&e)) {
        reason = detailed->reason();
        field = detailed->field();
      }
    } catch (const InputError& e) {
      status = grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, e.what());
    } catch (const std::exception& e) {
      spdlog::error("[{}] {} internal error: {}", call.request_id, method, escape_text(e.what()));
      // The text may name server files: it stays in the log, the caller gets the request id.
      std::string message = "internal error (request ";
      message.append(call.request_id).append("; the server log has the details)");
      status = grpc::Status(grpc::StatusCode::INTERNAL, message);
    }
  }
  // Messages may quote what the client sent: escaped before they reach the client or the log.
  if (!status.ok()) status = with_details(status, reason, field, call.request_id);
  server_metrics().rpcs.with({method, api::status_code_name(status.error_code())}).add();
  if (status.ok())
    spdlog::info("[{}] {} ok", call.request_id, method);
  else
    spdlog::info("[{}] {} -> {} {}", call.request_id, method, static_cast<int>(status.error_code()),
                 status.error_message());
  return status;
}

}  // namespace isocorr::server
