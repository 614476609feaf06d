#include "isocorr/output/map_files.h"

#include <charconv>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "isocorr/output/npy_array.h"
#include "isocorr/util/error.h"
#include "isocorr/util/file_bytes.h"

namespace isocorr {
namespace {

constexpr std::string_view kBinaryMagic("ICMAP1\0\0", 8);
constexpr size_t kBinaryHeaderBytes = kBinaryMagic.size() + 4;  // magic, uint32 count

std::ofstream open_for_writing(const std::string& path, std::ios::openmode mode = {}) {
  std::ofstream out(path, std::ios::out | std::ios::trunc | mode);
  if (!out) throw InputError("cannot write '" + path + "'");
  return out;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}


[[noreturn]] void fail(const std::string& path, const std::string& what) { throw InputError(path + ": " + what); }

uint32_t load_le32(std::string_view bytes, size_t at) {
  uint32_t value = 0;
  for (size_t i = 4; i-- > 0;) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

std::vector<int> parse_binary_map(std::string_view bytes, const std::string& path) {
  if (bytes.size() < kBinaryHeaderBytes)
    fail(path, "truncated ICMAP1 map: " + std::to_string(bytes.size()) + " bytes, fewer than its " +
                   std::to_string(kBinaryHeaderBytes) + "-byte header");
  const uint32_t count = load_le32(bytes, kBinaryMagic.size());
  const uint64_t expected = kBinaryHeaderBytes + 4 * static_cast<uint64_t>(count);
  if (bytes.size() != expected)
    fail(path, std::string(bytes.size() < expected ? "truncated ICMAP1 map" : "ICMAP1 count mismatch") +
                   ": the header declares " + std::to_string(count) + " indices (" + std::to_string(expected) +
                   " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
  std::vector<int> map(count);
  for (uint32_t k = 0; k < count; ++k) {
    map[k] = static_cast<int32_t>(load_le32(bytes, kBinaryHeaderBytes + 4 * static_cast<size_t>(k)));
    if (map[k] < kNoCounterpart)
      fail(path, "vertex " + std::to_string(k) + " maps to the negative index " + std::to_string(map[k]));
  }
  return map;
}

std::vector<int> parse_npy_map(std::string_view bytes, const std::string& path) {
  const std::vector<int64_t> values = parse_npy_integers(bytes, path);
  std::vector<int> map(values.size());
  for (size_t k = 0; k < values.size(); ++k) {
    if (values[k] < kNoCounterpart || values[k] > std::numeric_limits<int32_t>::max())
      fail(path, "vertex " + std::to_string(k) + " maps to " + std::to_string(values[k]) +
                     ", which is no vertex index (nor -1)");
    map[k] = static_cast<int>(values[k]);
  }
  return map;
}

std::vector<int> parse_text_map(const std::string& bytes, const std::string& path) {
  std::istringstream in(bytes);
  std::vector<std::string> lines;
  for (std::string text; std::getline(in, text);) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    lines.push_back(text);
  }
  // Trailing blank lines are harmless; a blank line inside would shift every later vertex.
  while (!lines.empty() && lines.back().find_first_not_of(" \t") == std::string::npos) lines.pop_back();
  std::vector<int> map;
  map.reserve(lines.size());
  for (size_t k = 0; k < lines.size(); ++k) {
    const std::string& s = lines[k];
    const size_t begin = s.find_first_not_of(" \t"), end = s.find_last_not_of(" \t");
    int value = -1;
    const char* first = begin == std::string::npos ? s.data() : s.data() + begin;
    const char* last = begin == std::string::npos ? s.data() : s.data() + end + 1;
    auto [ptr, ec] = std::from_chars(first, last, value);
    if (begin == std::string::npos || ec != std::errc() || ptr != last || value < kNoCounterpart)
      fail(path + ":" + std::to_string(k + 1), "expected one vertex index (or -1), found '" + s + "'");
    map.push_back(value);
  }
  return map;
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
  out.write(kBinaryMagic.data(), kBinaryMagic.size());
  auto put32 = [&](uint32_t value) {
    const unsigned char bytes[4] = {static_cast<unsigned char>(value), static_cast<unsigned char>(value >> 8),
                                    static_cast<unsigned char>(value >> 16), static_cast<unsigned char>(value >> 24)};
    out.write(reinterpret_cast<const char*>(bytes), 4);
  };
  put32(static_cast<uint32_t>(map.size()));
  for (int v : map) put32(static_cast<uint32_t>(v));
  if (!out) throw InputError("failed writing '" + path + "'");
}

void write_map_npy(const std::string& path, const std::vector<int>& map) {
  write_file_bytes(path, npy_bytes(map), "map file");
}

void write_values(const std::string& path, const std::vector<float>& values) {
  if (ends_with(path, ".npy")) return write_file_bytes(path, npy_bytes(values), "values file");
  char line[32];
  std::string text;
  for (const float value : values) {
    const int length = std::snprintf(line, sizeof line, "%.6g\n", value);
    text.append(line, static_cast<size_t>(length));
  }
  write_file_bytes(path, text, "values file");
}

void write_map(const std::string& path, const std::vector<int>& map) {
  if (ends_with(path, ".bin")) write_map_binary(path, map);
  else if (ends_with(path, ".npy")) write_map_npy(path, map);
  else write_map_text(path, map);
}

std::vector<int> read_map(const std::string& path) { return parse_map(read_file_bytes(path, "map file"), path); }

std::vector<int> parse_map(const std::string& bytes, const std::string& path) {
  if (bytes.starts_with(kBinaryMagic)) return parse_binary_map(bytes, path);
  if (looks_like_npy(bytes)) return parse_npy_map(bytes, path);
  // No text map starts with a letter: this is a binary map cut inside its magic, or one of
  // a version this reader does not know.
  if (bytes.starts_with("ICMAP"))
    fail(path, "starts like an ICMAP binary map but without the 8-byte magic \"ICMAP1\\0\\0\" (truncated, or "
               "another version)");
  return parse_text_map(bytes, path);
}

void check_map_fits(const std::vector<int>& map, int source_vertices, int target_vertices, bool may_have_no_counterpart) {
  if (map.size() != static_cast<size_t>(source_vertices))
    throw InputError("the map has " + std::to_string(map.size()) + " entries but the source has " +
                     std::to_string(source_vertices) + " vertices");
  for (size_t v = 0; v < map.size(); ++v)
    if (map[v] >= target_vertices || (map[v] < 0 && !(may_have_no_counterpart && map[v] == kNoCounterpart)))
      throw InputError("the map sends source vertex " + std::to_string(v) + " to " + std::to_string(map[v]) +
                       ", outside the target's " + std::to_string(target_vertices) + " vertices");
}

}  // namespace isocorr
