// The precise maps a match writes beside its vertex maps (--precise-out,
// --reverse-precise-out).
#pragma once

#include "commands.h"
#include "isocorr/transfer/surface_point.h"

namespace isocorr::cli {

void write_precise_outputs(const MatchJobFiles& files, const PreciseMap& forward, const PreciseMap& reverse);

}  // namespace isocorr::cli
