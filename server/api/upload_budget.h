// The bytes all uploads in progress may announce together. An upload holds its declared
// size from its header until it is stored or fails, which covers the server's memory peak
// (parsing and checking the whole mesh at the end), so concurrent uploads cannot exhaust it.
#pragma once

#include <cstdint>
#include <mutex>

namespace isocorr::server {

class UploadBudget {
 public:
  explicit UploadBudget(int64_t max_bytes) : max_bytes_(max_bytes) {}

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

  // Throws ServiceError(kResourceExhausted) when `bytes` do not fit beside the uploads
  // in progress.
  [[nodiscard]] Reservation reserve(int64_t bytes);

 private:
  void release(int64_t bytes);

  const int64_t max_bytes_;
  std::mutex mutex_;
  int64_t in_flight_ = 0;
};

}  // namespace isocorr::server
