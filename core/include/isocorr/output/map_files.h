// Dense map files: writing them in formats other tools read, and reading them back.
#pragma once

#include <string>
#include <vector>

namespace isocorr {

// The entry of a vertex without a counterpart: target vertices outside the image of a part
// (method = part) in a reverse map.
inline constexpr int kNoCounterpart = -1;

// Text: one 0-based target index per line, in source vertex order.
void write_map_text(const std::string& path, const std::vector<int>& map);
// Binary: "ICMAP1\0\0", uint32 count, then count little-endian int32 indices.
void write_map_binary(const std::string& path, const std::vector<int>& map);
// NumPy: a .npy array of int32 (numpy.load reads it).
void write_map_npy(const std::string& path, const std::vector<int>& map);
// Picks the format by extension: ".bin" is binary, ".npy" NumPy, anything else text.
void write_map(const std::string& path, const std::vector<int>& map);

// Per-vertex values (the confidence of each pair): float32 .npy when the name ends in
// ".npy", else text, one value per line.
void write_values(const std::string& path, const std::vector<float>& values);

// Reads a map in any of the three formats, known by its first bytes whatever its name:
// binary (the ICMAP1 magic), NumPy (any integer .npy array of shape (N,), as numpy.save
// writes int32 or int64), text otherwise (blank lines at the end are ignored). Throws InputError naming
// the file and the problem: a truncated binary map, a count that disagrees with the data,
// a text line that is not one integer, a negative index other than -1 (kNoCounterpart).
std::vector<int> read_map(const std::string& path);
// The same for a map already in memory; `name` stands for the file in messages.
std::vector<int> parse_map(const std::string& bytes, const std::string& name);

// Throws InputError unless `map` has one entry per source vertex, each a target vertex
// (or kNoCounterpart when `may_have_no_counterpart`: the reverse map of a part).
void check_map_fits(const std::vector<int>& map, int source_vertices, int target_vertices,
                    bool may_have_no_counterpart = false);

}  // namespace isocorr
