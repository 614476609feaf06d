// Match settings as a JSON object keyed by the schema's field names: the job journal's
// record of a job and the report's "settings". Kept apart from settings_schema.h so that
// only the translation units that write JSON include nlohmann/json.
#pragma once

#include <nlohmann/json.hpp>

#include "isocorr/settings/match_settings.h"

namespace isocorr {

// Every field of the table; a choice by its name; "landmarks" as a list of
// {"source_vertex", "target_vertex"} objects when there are any.
nlohmann::json settings_to_json(const MatchSettings& settings);

// Fields missing from `json` keep their defaults (records written by older versions);
// unknown keys are ignored. Throws InputError naming a field of the wrong JSON type (or the
// landmark entry, "landmarks[2]"); does not validate.
MatchSettings settings_from_json(const nlohmann::json& json);

}  // namespace isocorr
