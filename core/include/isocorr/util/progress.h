// Progress reporting and cooperative cancellation, shared by every long-running stage.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

#include "isocorr/util/error.h"

namespace isocorr {

struct Progress {
  std::string stage;   // "preprocess-source", "level0", "tracking", "dense", ...
  int level = 0;       // level k of the coarse-to-fine hierarchy (0 when not applicable)
  int levels = 0;      // K, the number of levels
  double fraction = 0; // overall completion in [0, 1]
};

// Passed down by the caller (CLI, service). Every member is optional.
struct JobControl {
  using Clock = std::chrono::steady_clock;

  std::function<void(const Progress&)> on_progress;  // may run on several threads at once
  const std::atomic<bool>* cancel_requested = nullptr;
  Clock::time_point deadline = Clock::time_point::max();  // the work ends with DeadlineExceeded past it
  // Workers the work may use (0 = all cores). How a call runs, not what it computes: no
  // result depends on it, so it lives here and not in any options struct.
  int threads = 0;

  void report(const Progress& progress) const {
    if (on_progress) on_progress(progress);
  }
  // Called at safe points inside loops; unwinds the job with Cancelled, or DeadlineExceeded.
  void check_cancelled() const {
    if (cancel_requested && cancel_requested->load(std::memory_order_relaxed)) throw Cancelled();
    if (deadline != Clock::time_point::max() && Clock::now() > deadline) throw DeadlineExceeded();
  }
  // The same cancellation, deadline and workers, without progress.
  JobControl cancellation_only() const {
    JobControl control;
    control.cancel_requested = cancel_requested;
    control.deadline = deadline;
    control.threads = threads;
    return control;
  }
  // The same control on `workers` workers: a stage that runs several calls side by side
  // shares its workers out among them.
  JobControl with_threads(int workers) const {
    JobControl control = *this;
    control.threads = workers;
    return control;
  }
};

}  // namespace isocorr
