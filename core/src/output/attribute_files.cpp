#include "isocorr/output/attribute_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/ply_properties.h"
#include "isocorr/output/npy_array.h"
#include "isocorr/util/error.h"
#include "isocorr/util/file_bytes.h"

namespace isocorr {
namespace {

// The numbers of one line, or false when a field is not a number.
bool parse_row(std::string line, std::vector<double>& row) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::replace(line.begin(), line.end(), ';', ' ');
  std::istringstream fields(line);
  row.clear();
  for (std::string field; fields >> field;) {
    char* end = nullptr;
    const double value = std::strtod(field.c_str(), &end);
    if (end != field.c_str() + field.size()) return false;
    row.push_back(value);
  }
  return true;
}

VertexTable parse_text_table(const std::string& bytes, const std::string& path) {
  VertexTable table;
  table.columns = 0;
  std::istringstream in(bytes);
  int line_number = 0;
  std::vector<double> row;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r,;") == std::string::npos) continue;
    const std::string where = path + ":" + std::to_string(line_number);
    if (!parse_row(line, row)) {
      if (table.rows == 0 && table.columns == 0) {  // a header
        table.columns = -1;
        continue;
      }
      throw InputError(where + ": a value is not a number: '" + line + "'");
    }
    if (table.columns <= 0) table.columns = static_cast<int>(row.size());
    if (static_cast<int>(row.size()) != table.columns)
      throw InputError(where + ": " + std::to_string(row.size()) + " values where the rows above have " +
                       std::to_string(table.columns));
    table.values.insert(table.values.end(), row.begin(), row.end());
    ++table.rows;
  }
  if (table.rows == 0) throw InputError(path + ": no rows of values");
  return table;
}

}  // namespace

VertexTable read_vertex_table(const std::string& path, const std::vector<std::string>& ply_properties) {
  if (path.ends_with(".ply") || path.ends_with(".PLY")) {
    if (ply_properties.empty()) throw InputError(path + ": name the vertex properties to read");
    VertexTable table{0, static_cast<int>(ply_properties.size()), read_ply_vertex_properties(path, ply_properties)};
    table.rows = static_cast<int>(table.values.size() / ply_properties.size());
    if (table.rows == 0) throw InputError(path + ": no vertices");
    return table;
  }
  const std::string bytes = read_file_bytes(path, "attribute file");
  if (!looks_like_npy(bytes)) return parse_text_table(bytes, path);
  NpyTable npy = parse_npy_table(bytes, path);
  if (npy.rows == 0) throw InputError(path + ": no rows of values");
  return {static_cast<int>(npy.rows), static_cast<int>(npy.columns), std::move(npy.values)};
}

void write_vertex_table(const std::string& path, const VertexTable& table) {
  if (path.ends_with(".npy")) return write_file_bytes(path, npy_bytes(table.values, table.columns), "attribute file");
  const char separator = path.ends_with(".csv") ? ',' : ' ';
  std::string text;
  char number[32];
  for (int r = 0; r < table.rows; ++r)
    for (int c = 0; c < table.columns; ++c) {
      const double value = table.values[static_cast<size_t>(r) * table.columns + c];
      const int length = std::isnan(value) ? std::snprintf(number, sizeof number, "nan")
                                           : std::snprintf(number, sizeof number, "%.9g", value);
      text.append(number, static_cast<size_t>(length));
      text += c + 1 == table.columns ? '\n' : separator;
    }
  write_file_bytes(path, text, "attribute file");
}

void write_labels(const std::string& path, const std::vector<int64_t>& labels) {
  if (path.ends_with(".npy")) {
    std::vector<int> narrow(labels.begin(), labels.end());
    return write_file_bytes(path, npy_bytes(narrow), "labels file");
  }
  std::string text;
  for (const int64_t label : labels) text += std::to_string(label) + '\n';
  write_file_bytes(path, text, "labels file");
}

std::vector<int64_t> labels_of(const VertexTable& table, const std::string& name) {
  if (table.columns != 1)
    throw InputError(name + ": labels are one column, the table has " + std::to_string(table.columns));
  std::vector<int64_t> labels(table.values.size());
  for (size_t r = 0; r < labels.size(); ++r) {
    const double value = table.values[r];
    if (!(std::abs(value) < 2147483648.0) || value != std::floor(value))
      throw InputError(name + ": row " + std::to_string(r) + " holds " + std::to_string(value) + ", not a label");
    labels[r] = static_cast<int64_t>(value);
  }
  return labels;
}

void write_coloured_ply(const std::string& path, const TriangleMesh& mesh, const VertexTable& colours) {
  if (colours.columns != 3) throw InputError("colours are three columns (red, green, blue), found " + std::to_string(colours.columns));
  if (colours.rows != mesh.num_vertices())
    throw InputError(std::to_string(colours.rows) + " colours for a mesh of " + std::to_string(mesh.num_vertices()) +
                     " vertices");
  const bool unit = std::all_of(colours.values.begin(), colours.values.end(),
                                [](double v) { return std::isnan(v) || (v >= 0 && v <= 1); });
  std::vector<std::array<unsigned char, 3>> rgb(mesh.num_vertices());
  for (size_t k = 0; k < colours.values.size(); ++k) {
    const double v = colours.values[k];
    rgb[k / 3][k % 3] = std::isnan(v) ? 128 : static_cast<unsigned char>(std::lround(std::clamp(unit ? 255 * v : v, 0.0, 255.0)));
  }
  write_ply(path, mesh, rgb);
}

}  // namespace isocorr
