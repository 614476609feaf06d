#include "storage/storage_failure.h"

#include <cerrno>
#include <cstring>

#include <spdlog/spdlog.h>

#include "service_error.h"

namespace isocorr::server {

bool is_out_of_space(int error_number) {
  return error_number == ENOSPC || error_number == EDQUOT || error_number == EFBIG;
}

void throw_write_failure(const std::string& action, const std::filesystem::path& path, int error_number) {
  spdlog::error("storage: {} '{}': {}", action, path.string(), std::strerror(error_number));
  const std::string message =
      is_out_of_space(error_number)
          ? "the server's disk is full (no space left for its data); retry when space has been freed"
          : std::string("the server cannot write its data (") + std::strerror(error_number) +
                "); retry later or tell the server's operator";
  throw ServiceError(ServiceError::Kind::kResourceExhausted, message);
}

void guard_storage_write(const std::string& action, const std::filesystem::path& path,
                         const std::function<void()>& body) {
  try {
    body();
  } catch (const std::filesystem::filesystem_error& e) {
    throw_write_failure(action, e.path1().empty() ? path : e.path1(), e.code().value());
  }
}

}  // namespace isocorr::server
