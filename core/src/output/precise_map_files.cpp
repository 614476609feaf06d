#include "isocorr/output/precise_map_files.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "isocorr/output/npy_array.h"
#include "isocorr/util/error.h"
#include "isocorr/util/file_bytes.h"

namespace isocorr {
namespace {

constexpr size_t kColumns = 4;        // face, three weights
constexpr double kWeightSlack = 1e-3;  // text files round the weights

// The point of one row, or an error naming `where` and what is wrong.
SurfacePoint point_of(double face, double w0, double w1, double w2, const std::string& where) {
  if (!(face >= -1) || face != std::floor(face) || face > 2147483647.0)
    throw InputError(where + ": the face is " + std::to_string(face) + ", not a face index (or -1)");
  SurfacePoint point{static_cast<int>(face), {static_cast<float>(w0), static_cast<float>(w1), static_cast<float>(w2)}};
  if (point.face < 0) return point;
  for (const double w : {w0, w1, w2})
    if (!std::isfinite(w) || w < -kWeightSlack)
      throw InputError(where + ": the weight " + std::to_string(w) + " is not a barycentric weight");
  if (std::abs(w0 + w1 + w2 - 1) > kWeightSlack)
    throw InputError(where + ": the weights sum to " + std::to_string(w0 + w1 + w2) + ", not 1");
  return point;
}

PreciseMap parse_text(const std::string& bytes, const std::string& path) {
  PreciseMap map;
  std::istringstream in(bytes);
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double face = 0, w0 = 0, w1 = 0, w2 = 0;
    std::string rest;
    const std::string where = path + ":" + std::to_string(line_number);
    if (!(fields >> face >> w0 >> w1 >> w2) || (fields >> rest))
      throw InputError(where + ": expected 'face w0 w1 w2', found '" + line + "'");
    map.push_back(point_of(face, w0, w1, w2, where));
  }
  return map;
}

}  // namespace

void write_precise_map(const std::string& path, const PreciseMap& map) {
  std::string bytes;
  if (path.ends_with(".npy")) {
    std::vector<double> rows;
    rows.reserve(map.size() * kColumns);
    for (const SurfacePoint& p : map) rows.insert(rows.end(), {double(p.face), p.weights[0], p.weights[1], p.weights[2]});
    bytes = npy_bytes(rows, kColumns);
  } else {
    char line[80];
    for (const SurfacePoint& p : map) {
      const int length = std::snprintf(line, sizeof line, "%d %.9g %.9g %.9g\n", p.face, p.weights[0], p.weights[1],
                                       p.weights[2]);
      bytes.append(line, static_cast<size_t>(length));
    }
  }
  write_file_bytes(path, bytes, "precise map");
}

PreciseMap read_precise_map(const std::string& path) {
  const std::string bytes = read_file_bytes(path, "precise map");
  if (!looks_like_npy(bytes)) return parse_text(bytes, path);
  const std::vector<double> rows = parse_npy_rows(bytes, path, kColumns);
  PreciseMap map;
  map.reserve(rows.size() / kColumns);
  for (size_t r = 0; r < rows.size(); r += kColumns)
    map.push_back(point_of(rows[r], rows[r + 1], rows[r + 2], rows[r + 3], path + ": row " + std::to_string(r / kColumns)));
  return map;
}

void check_precise_map_fits(const PreciseMap& map, int source_vertices, int target_faces) {
  if (static_cast<int>(map.size()) != source_vertices)
    throw InputError("the precise map has " + std::to_string(map.size()) + " points for a source of " +
                     std::to_string(source_vertices) + " vertices");
  for (size_t v = 0; v < map.size(); ++v)
    if (map[v].face >= target_faces)
      throw InputError("the precise map puts source vertex " + std::to_string(v) + " on face " +
                       std::to_string(map[v].face) + ", outside the target's " + std::to_string(target_faces) + " faces");
}

}  // namespace isocorr
