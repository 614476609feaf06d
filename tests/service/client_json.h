// Reading what the isocorr client printed with --json, for the service tests.
#pragma once

#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "server_process.h"

namespace isocorr::testing {

// The last JSON object a command printed (watch prints one per line).
inline nlohmann::json last_json(const CommandRun& run) {
  std::istringstream lines(run.out);
  nlohmann::json last = nlohmann::json::object();
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] == '{') last = nlohmann::json::parse(line);
  return last;
}

// The status code name of a failed command's {"error":{"code":...}}, "" when it did not fail.
inline std::string error_code(const CommandRun& run) {
  return last_json(run).value("error", nlohmann::json::object()).value("code", "");
}

}  // namespace isocorr::testing
