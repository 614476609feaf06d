// Job progress on stderr: a one-line bar on a terminal, one line per stage change otherwise.
// Used by the local match and by the remote commands (watch, match --server). The engine
// reports from its worker threads, so calls are serialised.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>

#include "isocorr/util/progress.h"

namespace isocorr::cli {

class ProgressPrinter {
 public:
  // `log_line` receives the one-line-per-stage messages when `terminal` is false (a bar is
  // drawn on stderr otherwise).
  explicit ProgressPrinter(
      std::function<void(const std::string&)> log_line = [](const std::string& line) { spdlog::info("{}", line); },
      bool terminal = isatty(STDERR_FILENO))
      : terminal_(terminal), log_line_(std::move(log_line)) {}
  void operator()(const Progress& p) {
    std::lock_guard lock(mutex_);
    if (terminal_) {
      const int width = 30, filled = static_cast<int>(p.fraction * width);
      std::fprintf(stderr, "\r[%-*s] %3d%% %-18s level %d/%d", width, std::string(filled, '#').c_str(),
                   static_cast<int>(p.fraction * 100), p.stage.c_str(), p.level, p.levels);
      if (p.stage == "done") std::fprintf(stderr, "\n");
    } else if (p.stage != last_stage_) {
      std::string line = p.stage == "done" ? "done" : "stage " + p.stage;
      // Levels belong to the coarse-to-fine stages only.
      if (p.levels > 0 && p.stage != "done")
        line += " (level " + std::to_string(p.level) + "/" + std::to_string(p.levels) + ")";
      log_line_(line);
    }
    last_stage_ = p.stage;
  }

 private:
  std::mutex mutex_;
  bool terminal_;
  std::function<void(const std::string&)> log_line_;
  std::string last_stage_;
};

}  // namespace isocorr::cli
