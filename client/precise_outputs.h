// The precise maps a match writes beside its vertex maps (--precise-out,
// --reverse-precise-out), computed from those maps and the mesh files, for an in-process
// match and a match on a server alike.
#pragma once

#include <vector>

#include "commands.h"
#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr::cli {

void write_precise_outputs(const MatchJobFiles& files, const TriangleMesh& source, const TriangleMesh& target,
                           const std::vector<int>& forward, const std::vector<int>& reverse);

}  // namespace isocorr::cli
