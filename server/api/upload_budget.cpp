#include "api/upload_budget.h"

#include <string>

#include "api/error_details.h"

namespace isocorr::server {

UploadBudget::Reservation UploadBudget::reserve(int64_t file_bytes) {
  const int64_t bytes = memory_for(file_bytes);
  std::lock_guard lock(mutex_);
  if (bytes > max_bytes_ - in_flight_)
    throw DetailedError(ServiceError::Kind::kResourceExhausted, "UPLOAD_BUDGET_EXHAUSTED", "",
                        "uploads in progress hold " + std::to_string(in_flight_) + " of the server's " +
                            std::to_string(max_bytes_) + " bytes of memory for uploads, and checking this one needs " +
                            std::to_string(bytes) + "; retry when they are done (isocorr-server --upload-memory)");
  in_flight_ += bytes;
  return Reservation(*this, bytes);
}

void UploadBudget::release(int64_t bytes) {
  std::lock_guard lock(mutex_);
  in_flight_ -= bytes;
}

}  // namespace isocorr::server
