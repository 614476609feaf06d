// Ground-truth correspondences in every form found in the benchmark data (shared/data):
// identity, .vts lists, FAUST prefix maps, TOPKIDS reference maps, sparse SHREC'07 feature
// points, partial-to-full index maps, and left/right symmetry maps for flip detection.
#pragma once

#include <string>
#include <vector>

namespace isocorr {

// Pairs (source vertex, true target vertex), 0-based in the files' numbering. When the
// dataset has a left/right symmetry, `mirrored_target[k]` is the mirror image of
// `target[k]` on the target (-1 where unknown); empty when there is none.
struct GroundTruth {
  std::vector<int> source;
  std::vector<int> target;
  std::vector<int> mirrored_target;
  std::string description;   // e.g. "vts: 5000 pairs, symmetric GT from B.sym.vts"
};

// One line of a dataset's pairs.tsv.
struct BenchmarkPair {
  std::string source_path;   // absolute or relative to the dataset folder, as resolved
  std::string target_path;
  std::string gt_kind;       // identity, vts, prefix6890, ref_to_null, sparse_vts, index_map:<file>
  std::string protocol;
};

// Reads `<dataset_dir>/pairs.tsv` (header line first); paths are resolved against the dataset dir.
std::vector<BenchmarkPair> read_pairs_tsv(const std::string& dataset_dir);

// Builds the ground truth for a pair of a dataset folder, following its README's format:
// finds the .vts / sym / ref files next to the meshes by name. `source_vertices` and
// `target_vertices` bound every index (InputError when a file refers outside them).
GroundTruth load_ground_truth(const std::string& dataset_dir, const BenchmarkPair& pair,
                              int source_vertices, int target_vertices);

}  // namespace isocorr
