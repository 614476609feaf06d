#include "storage/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "storage/storage_failure.h"

namespace isocorr::server {
namespace {

// Closes `fd` when it goes out of scope.
struct FileDescriptor {
  int fd;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

void fsync_path(const std::filesystem::path& path) {
  const FileDescriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) throw_write_failure("cannot open", path, errno);
  if (::fsync(file.fd) != 0) throw_write_failure("cannot fsync", path, errno);
}

void write_file_durably(const std::filesystem::path& path, const std::string& content) {
  const std::filesystem::path temp = path.string() + ".tmp";
  auto fail = [&](const char* action) {
    const int error_number = errno;
    ::unlink(temp.c_str());  // a failed write leaves nothing behind
    throw_write_failure(action, temp, error_number);
  };
  {
    const FileDescriptor file{::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644)};
    if (file.fd < 0) throw_write_failure("cannot create", temp, errno);
    size_t written = 0;
    while (written < content.size()) {
      const ssize_t n = ::write(file.fd, content.data() + written, content.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail("cannot write");
      written += static_cast<size_t>(n);
    }
    if (::fsync(file.fd) != 0) fail("cannot fsync");
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) fail("cannot rename into place");
  fsync_path(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));  // a bare name is in the working directory
}

std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path.string() + "'");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace isocorr::server
