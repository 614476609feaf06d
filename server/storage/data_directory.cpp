#include "storage/data_directory.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

#include "storage/durable_file.h"

namespace isocorr::server {
namespace fs = std::filesystem;

namespace {

constexpr const char* kLockFile = "server.lock";
constexpr const char* kLayoutFile = "layout";
// 1: result manifests name their job, both meshes and the settings.
constexpr const char* kCurrentLayout = "1\n";

bool has_entries(const fs::path& dir) {
  std::error_code error;
  return fs::is_directory(dir, error) && !fs::is_empty(dir, error);
}

}  // namespace

DataDirectoryLock::DataDirectoryLock(const fs::path& data_dir) {
  const fs::path path = data_dir / kLockFile;
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot open " + path.string() + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    std::string holder;
    try {
      holder = read_whole_file(path);
    } catch (const std::exception&) {
    }
    while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
    ::close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK) throw std::runtime_error("cannot lock " + path.string() + ": " + std::strerror(error));
    throw std::runtime_error("the data directory " + data_dir.string() + " is in use by another isocorr-server (pid " +
                             (holder.empty() ? std::string("unknown") : holder) +
                             "); two servers must not share a data directory");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int error = errno;
    ::close(fd_);
    throw std::runtime_error("cannot write " + path.string() + ": " + std::strerror(error));
  }
}

DataDirectoryLock::~DataDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock; the file stays, with the last holder's pid
}

bool predates_current_layout(const fs::path& data_dir) {
  std::error_code error;
  return !fs::exists(data_dir / kLayoutFile, error) &&
         (has_entries(data_dir / "jobs") || has_entries(data_dir / "results"));
}

void mark_layout_current(const fs::path& data_dir) { write_file_durably(data_dir / kLayoutFile, kCurrentLayout); }

}  // namespace isocorr::server
