// Cuts partial shapes out of a full mesh, with the exact vertex correspondence back to it:
// the test data of part matching, generated from the benchmark meshes instead of stored,
// since their licences forbid copies.
#pragma once

#include <string>
#include <vector>

#include "isocorr/eval/ground_truth.h"
#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

enum class CutKind {
  kGeodesicBall,  // removes the geodesic ball around one vertex (a missing limb or region)
  kPlane,         // removes everything on one side of a plane (half a body)
  kHoles,         // removes several smaller geodesic balls (a scan with holes)
};

struct CutSpec {
  CutKind kind = CutKind::kGeodesicBall;
  double keep_area = 0.7;  // share of the full area left, in (0, 1)
  int holes = 3;           // kHoles: how many balls share the removed area
  unsigned seed = 1;       // picks the centres (kGeodesicBall, kHoles) or the normal (kPlane)
};

struct PartialShape {
  TriangleMesh mesh;
  std::vector<int> full_vertex;  // vertex of the full mesh each part vertex is a copy of
  double kept_area = 0;          // share of the full area the part has
  std::string description;       // e.g. "geodesic ball at vertex 812, 70% of the area kept"
};

// Removes faces by `spec`, keeps the largest connected piece of what is left and renumbers
// its vertices compactly. Faces are removed in the cut's order until no piece is larger
// than the kept share, so the part keeps that share within about one ring of faces also
// when the cut splits off a limb (the smaller pieces go with the cut); it keeps less only
// where removing one more face splits the largest piece. Deterministic for a given mesh
// and spec. Throws InputError when nothing usable is left.
PartialShape cut_partial_shape(const TriangleMesh& full, const CutSpec& spec);

// A full pair's ground truth carried through the cuts: restricted to the source part (and,
// when the target was cut too, to points whose image and mirror image were kept), in the
// parts' vertex numbers. `source_vertices` and `target_vertices` count the full meshes.
GroundTruth ground_truth_of_parts(const GroundTruth& full, const PartialShape& source_part, int source_vertices,
                                  const PartialShape* target_part, int target_vertices);

// "ball", "plane" or "holes" (InputError otherwise).
CutKind parse_cut_kind(const std::string& name);
const char* cut_kind_name(CutKind kind);

}  // namespace isocorr
