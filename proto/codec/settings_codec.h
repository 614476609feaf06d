// isocorr.v1.MatchSettings <-> isocorr::MatchSettings, shared by the server and the client.
// Unset proto fields keep the engine's defaults; the reverse direction sets every field.
// Neither checks ranges (MatchSettings::validate does); settings_from_proto throws
// InputError for an enum value this version does not know. The landmarks, a repeated field
// outside the settings table, are copied as they are.
#pragma once

#include "isocorr/settings/match_settings.h"
#include "isocorr/v1/isocorr.pb.h"

namespace isocorr::api {

MatchSettings settings_from_proto(const v1::MatchSettings& proto);
v1::MatchSettings settings_to_proto(const MatchSettings& settings);

}  // namespace isocorr::api
