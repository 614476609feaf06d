// The memory all uploads in progress may take together. An upload holds, from its header
// until it is stored or fails, the memory its declared size can make the server take: its
// bytes, held twice while checked, and the reading and cleaning peak (mesh_io.h). So
// concurrent uploads, hostile or not, cannot exhaust the server's memory.
#pragma once

#include <cstdint>
#include <mutex>

#include "isocorr/mesh/mesh_io.h"

namespace isocorr::server {

class UploadBudget {
 public:
  // Memory per byte of an upload's declared size.
  static constexpr int64_t kMemoryPerFileByte = kReadingPeakPerFileByte + 2;
  static int64_t memory_for(int64_t file_bytes) { return kMemoryPerFileByte * file_bytes; }

  explicit UploadBudget(int64_t max_memory_bytes) : max_bytes_(max_memory_bytes) {}

  // Gives its bytes back when destroyed.
  class Reservation {
   public:
    Reservation(UploadBudget& budget, int64_t bytes) : budget_(budget), bytes_(bytes) {}
    Reservation(const Reservation&) = delete;
    Reservation& operator=(const Reservation&) = delete;
    ~Reservation() { budget_.release(bytes_); }

   private:
    UploadBudget& budget_;
    int64_t bytes_;
  };

  // Holds memory_for(file_bytes). Throws ServiceError(kResourceExhausted) when that does not
  // fit beside the uploads in progress.
  [[nodiscard]] Reservation reserve(int64_t file_bytes);

 private:
  void release(int64_t bytes);

  const int64_t max_bytes_;
  std::mutex mutex_;
  int64_t in_flight_ = 0;
};

}  // namespace isocorr::server
