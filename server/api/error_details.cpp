#include "api/error_details.h"

#include "api/request_limits.h"
#include "codec/call_metadata.h"
#include "google/rpc/error_details.pb.h"
#include "google/rpc/status.pb.h"

namespace isocorr::server {

grpc::Status with_details(const grpc::Status& status, const std::string& reason, const std::string& field,
                          const std::string& request_id) {
  const std::string message = escape_text(status.error_message());
  if (!status.error_details().empty()) return grpc::Status(status.error_code(), message, status.error_details());
  google::rpc::Status details;
  details.set_code(static_cast<int>(status.error_code()));
  details.set_message(message);
  google::rpc::ErrorInfo info;
  info.set_reason(reason.empty() ? api::status_code_name(status.error_code()) : reason);
  info.set_domain(kErrorDomain);
  if (!request_id.empty()) (*info.mutable_metadata())["request_id"] = request_id;
  if (!field.empty()) (*info.mutable_metadata())["field"] = field;
  details.add_details()->PackFrom(info);
  if (!field.empty() && status.error_code() == grpc::StatusCode::INVALID_ARGUMENT) {
    google::rpc::BadRequest bad_request;
    auto* violation = bad_request.add_field_violations();
    violation->set_field(field);
    violation->set_description(message);
    details.add_details()->PackFrom(bad_request);
  }
  return grpc::Status(status.error_code(), message, details.SerializeAsString());
}

}  // namespace isocorr::server
