// Writing dense maps in formats other tools read.
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

}  // namespace isocorr
