// Fetching a finished job's result (DownloadResult stream) and writing it as files.
#pragma once

#include <string>
#include <vector>

#include "remote/connection.h"

namespace isocorr::cli {

struct DownloadedResult {
  std::vector<int> forward, reverse;
  std::vector<float> forward_confidence, reverse_confidence;
  std::string report_json;
};

// Fetches `parts` (all when empty) and checks each arrived whole. Throws RpcError.
DownloadedResult download_result(Connection& connection, const std::string& job_name,
                                 const std::vector<v1::ResultPart>& parts);

// Text, one value per line in vertex order, as `isocorr match` writes its outputs.
void write_values_text(const std::string& path, const std::vector<float>& values);

}  // namespace isocorr::cli
