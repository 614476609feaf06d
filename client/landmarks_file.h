// `--landmarks FILE`: known correspondences for a match (MatchSettings::landmarks), one
// `source_vertex target_vertex` pair per line in the files' 0-based vertex numbering; '#'
// starts a comment and blank lines are allowed. Every refusal names the file and the line.
#pragma once

#include <string>
#include <vector>

#include "isocorr/settings/match_settings.h"

namespace isocorr::cli {

// Where each landmark of a match came from, for messages that name a line.
struct LandmarksFile {
  std::string path;        // empty: no --landmarks
  std::vector<int> lines;  // 1-based line of each landmark, in order
};

// Reads the file into `landmarks` (replacing them) and `file`. Throws InputError
// "landmarks file 'F' line N: ..." for malformed lines, a repeated pair and a vertex given
// two partners.
void read_landmarks_file(const std::string& path, std::vector<Landmark>& landmarks, LandmarksFile& file);

// Throws the same InputError for the first landmark beyond the meshes' vertex counts. Does
// nothing without a file (landmarks from elsewhere are checked by the match).
void check_landmarks_fit(const LandmarksFile& file, const std::vector<Landmark>& landmarks, int source_vertices,
                         int target_vertices);

}  // namespace isocorr::cli
