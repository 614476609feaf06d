#include "storage/quarantine.h"

#include <chrono>

#include <spdlog/spdlog.h>

namespace isocorr::server {
namespace fs = std::filesystem;

void Quarantine::set_aside(const std::string& kind, const fs::path& path, const std::string& why) const {
  const fs::path destination = dir_ / kind / path.filename();
  std::error_code error;
  fs::create_directories(destination.parent_path(), error);
  fs::remove_all(destination, error);
  fs::rename(path, destination, error);
  if (!error) {
    spdlog::error("storage: {} is corrupted ({}); moved to {}", path.string(), why, destination.string());
    return;
  }
  fs::remove_all(path, error);
  spdlog::error("storage: {} is corrupted ({}); it could not be moved to {}, so it was deleted", path.string(), why,
                destination.string());
}

void Quarantine::keep_copy(const std::string& kind, const fs::path& path, const std::string& why) const {
  const fs::path destination = dir_ / kind / path.filename();
  std::error_code error;
  fs::create_directories(destination.parent_path(), error);
  fs::copy_file(path, destination, fs::copy_options::overwrite_existing, error);
  if (error)
    spdlog::error("storage: {} is corrupted ({}); cannot copy it to {}: {}", path.string(), why, destination.string(),
                  error.message());
  else
    spdlog::error("storage: {} is corrupted ({}); copied to {}", path.string(), why, destination.string());
}

bool Quarantine::holds(const std::string& kind, const std::string& file_name) const {
  std::error_code error;
  return fs::exists(dir_ / kind / file_name, error);
}

void Quarantine::archive(const std::string& kind, const std::string& file_name) const {
  const fs::path path = dir_ / kind / file_name;
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const fs::path dated = path.string() + ".repaired-" +
                         std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(now).count());
  std::error_code error;
  if (fs::exists(path, error)) fs::rename(path, dated, error);
  if (error) spdlog::error("storage: cannot rename {} to {}: {}", path.string(), dated.string(), error.message());
}

}  // namespace isocorr::server
