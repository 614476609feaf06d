// Turns a loaded mesh into one the engine can trust, without ever renumbering the output.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "isocorr/mesh/coordinate_normalisation.h"
#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

struct CleaningOptions {
  // Vertices closer than this fraction of the bounding-box diagonal are welded, where the
  // surface is open (vertices on boundary edges or unused); coincident vertices inside closed
  // fans are points where the surface touches itself and stay apart.
  double weld_tolerance = 1e-9;
  // Keep only the largest connected component (by area); other vertices are mapped to
  // their nearest kept vertex. When false, several components are an InputError.
  bool keep_largest_component = true;
  // Repair edges shared by more than two faces by keeping, on each, the two faces that best
  // continue the surface (the flattest pair) and dropping the rest. Real benchmark meshes
  // need it: TOPKIDS kid00, the reference shape of every TOPKIDS pair, has a stray triangle
  // hanging off one edge. When false, such an edge is an InputError.
  bool repair_non_manifold_edges = true;
};

// The engine's mesh plus the bridge back to the file's numbering.
struct CleanMesh {
  TriangleMesh mesh;                  // compact, consistently oriented (outward when closed), in
                                      // normalised coordinates (coordinate_normalisation.h)
  CoordinateNormalisation normalisation;  // from the input's coordinates to the mesh's
  std::vector<int> input_to_clean;    // for every input vertex, its vertex in `mesh`
  std::vector<int> clean_to_input;    // for every vertex of `mesh`, one input vertex
  // For every face of `mesh`, an input face with the same corners once welded, and which
  // of the clean face's corners each of the input face's corners is (cleaning may turn a
  // face): points on the clean mesh go back to the file's faces.
  struct InputFace {
    int face = -1;
    std::array<unsigned char, 3> clean_corner{0, 1, 2};
  };
  std::vector<InputFace> clean_face_origins;
  std::vector<std::string> repairs;   // each repair done, in words, for the report
};

// Validates, normalises the coordinates (exactly, by a power of two and a shift) and repairs:
// welds duplicate vertices, drops degenerate and duplicate faces,
// drops all but two faces on every non-manifold edge, drops unreferenced vertices (mapped
// to the nearest kept vertex), keeps the largest component, makes face orientation
// consistent and outward. Non-manifold vertices (separate fans meeting at one vertex) are
// kept as they are: nothing downstream needs a single fan per vertex. Throws InputError for
// what cannot be repaired: no faces left, non-manifold edges when their repair is off, a
// non-orientable surface.
CleanMesh clean_mesh(const TriangleMesh& input, const CleaningOptions& options = {});

// Matching needs level-0 samples far apart and a hierarchy below them: fewer vertices than
// this after cleaning cannot be matched.
inline constexpr int kMinMatchableVertices = 16;

// Throws InputError unless a cleaned mesh can be matched. Every job checks it, and an
// upload checks it with the default cleaning options, so an accepted upload can be matched.
void check_matchable(const CleanMesh& clean);

}  // namespace isocorr
