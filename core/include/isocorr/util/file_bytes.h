// Whole files as bytes, for the readers and writers of maps, precise maps and attribute
// tables. Both throw InputError naming `what` ("map file", "precise map", ...) and the path.
#pragma once

#include <string>

namespace isocorr {

std::string read_file_bytes(const std::string& path, const std::string& what);
void write_file_bytes(const std::string& path, const std::string& bytes, const std::string& what);

}  // namespace isocorr
