// Dense map files: writing them in formats other tools read, and reading them back.
#pragma once

#include <string>
#include <vector>

namespace isocorr {

// Text: one 0-based target index per line, in source vertex order.
void write_map_text(const std::string& path, const std::vector<int>& map);
// Binary: "ICMAP1\0\0", uint32 count, then count little-endian int32 indices.
void write_map_binary(const std::string& path, const std::vector<int>& map);
// Picks the format by extension: ".bin" is binary, anything else text.
void write_map(const std::string& path, const std::vector<int>& map);

// Reads a map in either format: binary when the file starts with the ICMAP1 magic, whatever
// its name, text otherwise (blank lines at the end are ignored). Throws InputError naming
// the file and the problem: a truncated binary map, a count that disagrees with the data,
// a text line that is not one integer, a negative index.
std::vector<int> read_map(const std::string& path);
// The same for a map already in memory; `name` stands for the file in messages.
std::vector<int> parse_map(const std::string& bytes, const std::string& name);

// Throws InputError unless `map` has one entry per source vertex, each a target vertex.
void check_map_fits(const std::vector<int>& map, int source_vertices, int target_vertices);

}  // namespace isocorr
