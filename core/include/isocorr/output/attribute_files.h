// Per-vertex attribute files for `isocorr transfer`: tables of one row per vertex.
//   text (.csv, .txt, anything else): values separated by commas or white space, one row per
//   line; '#' starts a comment; a first line that is not numbers is a header and skipped;
//   .npy: a numeric array of shape (N,) or (N, M) (numpy.save writes it);
//   .ply: the named vertex properties of a mesh file (by default its colours).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/transfer/attribute_transfer.h"

namespace isocorr {

// Vertex colours, the properties a .ply table is read from unless others are named.
inline const std::vector<std::string> kPlyColourProperties = {"red", "green", "blue"};

// Throws InputError naming the file and line: rows of different lengths, a value that is
// no number, an empty table, a .ply property the vertices lack.
VertexTable read_vertex_table(const std::string& path,
                              const std::vector<std::string>& ply_properties = kPlyColourProperties);

// .npy: float64 (N, M), or (N,) for one column; .csv: comma-separated; else space-separated.
// NaN (an unmatched vertex) is written as "nan".
void write_vertex_table(const std::string& path, const VertexTable& table);

// Labels: .npy int64 (N,), else one integer per line.
void write_labels(const std::string& path, const std::vector<int64_t>& labels);

// The table's integers, one column; throws InputError naming the row of a value that is
// not a whole number.
std::vector<int64_t> labels_of(const VertexTable& table, const std::string& name);

// Writes `mesh` as a binary PLY with the table's three columns as vertex colours: values
// in [0, 1] (all of them) are scaled by 255, others clamped to [0, 255]; NaN is grey.
void write_coloured_ply(const std::string& path, const TriangleMesh& mesh, const VertexTable& colours);

}  // namespace isocorr
