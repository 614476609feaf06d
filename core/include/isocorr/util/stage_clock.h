// Time per pipeline stage, for the report, the job summary and the benchmark's profile.
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <ctime>
#include <string>
#include <vector>

namespace isocorr {

struct StageTiming {
  std::string stage;
  double seconds = 0;      // wall clock
  // The process's CPU time over the stage, all its threads (in a server running jobs side
  // by side, theirs too: the benchmark's profile reads it, the report does not).
  double cpu_seconds = 0;
  double peak_mb = 0;      // the process's peak resident memory so far, at the stage's end
};

// Each finish() records the time since the previous one (or since construction).
class StageClock {
 public:
  explicit StageClock(std::vector<StageTiming>& timings) : timings_(timings) {}
  void finish(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    timings_.push_back({stage, std::chrono::duration<double>(now - start_).count(),
                        static_cast<double>(cpu - cpu_start_) / CLOCKS_PER_SEC, usage.ru_maxrss / 1024.0});
    start_ = now;
    cpu_start_ = cpu;
  }

 private:
  std::vector<StageTiming>& timings_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::clock_t cpu_start_ = std::clock();
};

}  // namespace isocorr
