// A job record as the journal writes it to jobs/<id>.json, and reading one back. A record
// read back may have been cut by a crash or altered on disk, so reading trusts nothing.
#pragma once

#include <nlohmann/json.hpp>

#include "storage/job_record.h"

namespace isocorr::server {

nlohmann::json record_to_json(const JobRecord& job);

// Throws a std::exception naming the first field that is missing, of the wrong type or out
// of its field's range (then the record is unreadable; the journal decides what follows).
JobRecord record_from_json(const nlohmann::json& j);

}  // namespace isocorr::server
