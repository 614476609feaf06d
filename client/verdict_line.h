// The last line of a match, local or on a server: what the result's verdict says.
#pragma once

#include <string>
#include <vector>

namespace isocorr::cli {

// A warning naming each reason when `status` is "suspect", an info line when "ok"; nothing
// for a result stored before verdicts ("").
void log_verdict(const std::string& status, const std::vector<std::string>& reasons);

}  // namespace isocorr::cli
