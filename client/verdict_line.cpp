#include "verdict_line.h"

#include <spdlog/spdlog.h>

namespace isocorr::cli {

void log_verdict(const std::string& status, const std::vector<std::string>& reasons) {
  if (status == "ok") {
    spdlog::info("verdict: ok");
    return;
  }
  if (status.empty()) return;
  std::string joined;
  for (const std::string& reason : reasons) joined += (joined.empty() ? "" : "; ") + reason;
  spdlog::warn("verdict: {} ({}); look at this map before using it, e.g. with isocorr render", status, joined);
}

}  // namespace isocorr::cli
