// Failures of the data directory as callers see them. A write that fails (full disk, quota,
// file-size limit, read-only or failing device) is ServiceError(kResourceExhausted) with a
// message that names no server path: the path and the system's reason go to the log.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace isocorr::server {

// ENOSPC, EDQUOT and EFBIG (a file-size limit): the disk is full as far as we are concerned.
bool is_out_of_space(int error_number);

// Logs `action` on `path` with the system's reason and throws the path-free ServiceError.
[[noreturn]] void throw_write_failure(const std::string& action, const std::filesystem::path& path, int error_number);

// Runs `body` (std::filesystem calls on the data directory); a std::filesystem_error it
// throws becomes a write failure as above.
void guard_storage_write(const std::string& action, const std::filesystem::path& path,
                         const std::function<void()>& body);

}  // namespace isocorr::server
