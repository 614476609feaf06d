// Precise map files (precise_map.h): one point per source vertex, as a target face and its
// corners' weights.
//   text: one line per source vertex, "face w0 w1 w2" (face -1: unmatched);
//   .npy: a float64 array of shape (N, 4), the same columns (numpy.load reads it).
#pragma once

#include <string>

#include "isocorr/transfer/precise_map.h"

namespace isocorr {

// Picks the format by extension: ".npy" NumPy, anything else text.
void write_precise_map(const std::string& path, const PreciseMap& map);

// Reads either format, known by its first bytes. Throws InputError naming the file (and
// line) for a face that is no integer of at least -1, or weights that are not finite,
// non-negative and summing to 1 (within 1e-3).
PreciseMap read_precise_map(const std::string& path);

// Throws InputError unless `map` has one point per source vertex, each on a target face.
void check_precise_map_fits(const PreciseMap& map, int source_vertices, int target_faces);

}  // namespace isocorr
