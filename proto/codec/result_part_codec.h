// isocorr.v1.ResultPart <-> isocorr::ResultPart, shared by the server and the client.
// The API's values are the engine's in order, from 1 (0 is UNSPECIFIED); a test checks it.
#pragma once

#include <optional>

#include "isocorr/output/match_output.h"
#include "isocorr/v1/isocorr.pb.h"

namespace isocorr::api {

// nullopt for UNSPECIFIED and for values this version does not know.
std::optional<ResultPart> result_part_from_proto(int value);
v1::ResultPart result_part_to_proto(ResultPart part);

}  // namespace isocorr::api
