// Fetching a finished job's result (DownloadResult stream).
#pragma once

#include <string>
#include <vector>

#include "isocorr/output/match_output.h"
#include "remote/connection.h"

namespace isocorr::cli {

// Fetches `parts` (all when empty) into the engine's own result type; parts not asked
// for stay empty. Throws RpcError; DATA_LOSS when a map does not have one entry per vertex
// or holds an index outside the other mesh (checked against the job's vertex counts).
MatchOutput download_result(Connection& connection, const std::string& job_name, const std::vector<ResultPart>& parts);

}  // namespace isocorr::cli
