#include "isocorr/output/map_files.h"

#include <cstdint>
#include <fstream>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

std::ofstream open_for_writing(const std::string& path, std::ios::openmode mode = {}) {
  std::ofstream out(path, std::ios::out | std::ios::trunc | mode);
  if (!out) throw InputError("cannot write '" + path + "'");
  return out;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void write_map_text(const std::string& path, const std::vector<int>& map) {
  auto out = open_for_writing(path);
  std::string buffer;
  buffer.reserve(map.size() * 7);
  for (int v : map) buffer += std::to_string(v) + '\n';
  out << buffer;
  if (!out) throw InputError("failed writing '" + path + "'");
}

void write_map_binary(const std::string& path, const std::vector<int>& map) {
  auto out = open_for_writing(path, std::ios::binary);
  const char magic[8] = {'I', 'C', 'M', 'A', 'P', '1', 0, 0};
  out.write(magic, sizeof magic);
  auto put32 = [&](uint32_t value) {
    const unsigned char bytes[4] = {static_cast<unsigned char>(value), static_cast<unsigned char>(value >> 8),
                                    static_cast<unsigned char>(value >> 16), static_cast<unsigned char>(value >> 24)};
    out.write(reinterpret_cast<const char*>(bytes), 4);
  };
  put32(static_cast<uint32_t>(map.size()));
  for (int v : map) put32(static_cast<uint32_t>(v));
  if (!out) throw InputError("failed writing '" + path + "'");
}

void write_map(const std::string& path, const std::vector<int>& map) {
  if (ends_with(path, ".bin")) write_map_binary(path, map);
  else write_map_text(path, map);
}

}  // namespace isocorr
