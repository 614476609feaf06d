// Wall-clock time per pipeline stage, for the report and the job summary.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace isocorr {

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

// Each finish() records the time since the previous one (or since construction).
class StageClock {
 public:
  explicit StageClock(std::vector<StageTiming>& timings) : timings_(timings) {}
  void finish(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    timings_.push_back({stage, std::chrono::duration<double>(now - start_).count()});
    start_ = now;
  }

 private:
  std::vector<StageTiming>& timings_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace isocorr
