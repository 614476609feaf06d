// What the data directory holds besides meshes, jobs and results: the lock that keeps a
// second server out (<data-dir>/server.lock, holding the holder's pid) and the version of
// its layout (<data-dir>/layout), written once a server has brought an older directory up
// to date. Results written before the layout file existed may lack a manifest or its job
// binding and are adopted once; in an up-to-date directory such a result is lost data.
#pragma once

#include <filesystem>

namespace isocorr::server {

// An exclusive flock on <data-dir>/server.lock for as long as it lives; the kernel
// releases it when the process dies, kill -9 included.
class DataDirectoryLock {
 public:
  // Throws std::runtime_error naming the holder's pid when another process holds it.
  explicit DataDirectoryLock(const std::filesystem::path& data_dir);
  ~DataDirectoryLock();
  DataDirectoryLock(const DataDirectoryLock&) = delete;
  DataDirectoryLock& operator=(const DataDirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// True for a directory that holds jobs or results but no layout file: written by a server
// from before manifests were bound to their jobs.
bool predates_current_layout(const std::filesystem::path& data_dir);
// Records that the directory is up to date (durably); later starts adopt nothing.
void mark_layout_current(const std::filesystem::path& data_dir);

}  // namespace isocorr::server
