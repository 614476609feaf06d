#include "precise_outputs.h"

#include "isocorr/output/precise_map_files.h"

namespace isocorr::cli {

void write_precise_outputs(const MatchJobFiles& files, const PreciseMap& forward, const PreciseMap& reverse) {
  if (!files.precise_output.empty()) write_precise_map(files.precise_output, forward);
  if (!files.reverse_precise_output.empty()) write_precise_map(files.reverse_precise_output, reverse);
}

}  // namespace isocorr::cli
