// Files that survive a crash: write to a temporary name, fsync, rename, fsync the
// directory. After `write_file_durably` returns, a kill -9 or power loss leaves either the
// old content or the new one, never a torn file.
#pragma once

#include <filesystem>
#include <string>

namespace isocorr::server {

// Both throw ServiceError(kResourceExhausted) without the path (storage_failure.h) and leave
// no temporary file behind.
void write_file_durably(const std::filesystem::path& path, const std::string& content);
// fsync of one file or directory (makes a rename or a new entry durable).
void fsync_path(const std::filesystem::path& path);
// Whole file; throws std::runtime_error naming the file when it cannot be read.
std::string read_whole_file(const std::filesystem::path& path);

}  // namespace isocorr::server
