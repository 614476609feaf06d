#include "precise_outputs.h"

#include "isocorr/output/precise_map_files.h"

namespace isocorr::cli {

void write_precise_outputs(const MatchJobFiles& files, const TriangleMesh& source, const TriangleMesh& target,
                           const std::vector<int>& forward, const std::vector<int>& reverse) {
  if (!files.precise_output.empty())
    write_precise_map(files.precise_output, precise_map(source, target, forward, files.settings.threads));
  if (!files.reverse_precise_output.empty())
    write_precise_map(files.reverse_precise_output, precise_map(target, source, reverse, files.settings.threads));
}

}  // namespace isocorr::cli
