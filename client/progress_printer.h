// Job progress on stderr: a one-line bar on a terminal, one line per stage change otherwise.
// Used by the local match and by the remote commands (watch, match --server).
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include <spdlog/spdlog.h>

#include "isocorr/util/progress.h"

namespace isocorr::cli {

class ProgressPrinter {
 public:
  ProgressPrinter() : terminal_(isatty(STDERR_FILENO)) {}
  void operator()(const Progress& p) {
    if (terminal_) {
      const int width = 30, filled = static_cast<int>(p.fraction * width);
      std::fprintf(stderr, "\r[%-*s] %3d%% %-18s level %d/%d", width, std::string(filled, '#').c_str(),
                   static_cast<int>(p.fraction * 100), p.stage.c_str(), p.level, p.levels);
      if (p.stage == "done") std::fprintf(stderr, "\n");
    } else if (p.stage != last_stage_) {
      spdlog::info("stage {} (level {}/{})", p.stage, p.level, p.levels);
    }
    last_stage_ = p.stage;
  }

 private:
  bool terminal_;
  std::string last_stage_;
};

}  // namespace isocorr::cli
