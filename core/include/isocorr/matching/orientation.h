// Does a map keep the handedness of small triangles? An intrinsic isometry cannot tell a
// shape from its mirror (the prototype measured a 0.9% D_iso gap on TOSCA,
// docs/decisions.md), but a mirror reverses orientation: ground-truth maps keep 92-100% of
// triangles, mirrored ones 1-9%.
// Needs consistently oriented meshes, which clean_mesh guarantees.
#pragma once

#include <vector>

#include "isocorr/matching/sample_pair.h"

namespace isocorr {

// Over sample pairs: each matched sample forms a triangle with two nearby matched samples
// (the best-spread pair at a few sample spacings, by vertex-accurate images); the result is the fraction of these
// triangles whose image has the same handedness relative to the surface normal.
double orientation_agreement(const PreprocessedShape& source, const PreprocessedShape& target,
                             const std::vector<SamplePair>& pairs);

// The same in two halves, for many pair lists with the same source samples (tracking's
// maps): the triangles are the source's, the count of kept ones the target's.
struct PairTriangle {
  int a, b, c;    // indices into the pair list
  bool positive;  // handedness on the source
};
std::vector<PairTriangle> orientation_triangles(const PreprocessedShape& source, const std::vector<SamplePair>& pairs);
double orientation_agreement(const PreprocessedShape& target, const std::vector<SamplePair>& pairs,
                             const std::vector<PairTriangle>& triangles);

// The same test for one new pair while tracking. Where extremities are the only level-0
// samples, a map and its front/back mirror (chest to back, toes to heels) agree at level 0
// and stay close in D_iso, so a tracker choosing by D_iso alone drifts into the mirror on
// part of the body. The guard takes triangles formed by a new source sample and two
// matched samples near it; a target vertex passes when most of them keep handedness.
// The source's half (guard_corners: the triangles, over indices into `matched`) depends on
// the matched source samples only, so tracking computes it once for all its maps.
struct GuardCorners {
  int b, c;       // indices into the matched pairs
  bool positive;  // handedness of (new sample, b, c) on the source
};
std::vector<GuardCorners> guard_corners(const PreprocessedShape& source, const std::vector<SamplePair>& matched,
                                        int source_vertex, float min_distance);

class HandednessGuard {
 public:
  HandednessGuard(const PreprocessedShape& target, const std::vector<SamplePair>& matched,
                  const std::vector<GuardCorners>& corners);
  HandednessGuard(const PreprocessedShape& source, const PreprocessedShape& target,
                  const std::vector<SamplePair>& matched, int source_vertex, float min_distance)
      : HandednessGuard(target, matched, guard_corners(source, matched, source_vertex, min_distance)) {}
  bool accepts(int target_vertex) const;

 private:
  struct Triangle {
    int target_b, target_c;  // images of the two matched corners
    bool positive;           // handedness on the source
  };
  const PreprocessedShape& target_;
  std::vector<Triangle> triangles_;
};

// Over a dense vertex map (clean-mesh numbering): the fraction of source faces whose three
// images span a triangle of the same handedness (faces mapped to a point, or with a vertex
// left unmapped (-1), are skipped).
double dense_orientation_agreement(const TriangleMesh& source, const std::vector<Vec3>& source_normals,
                                   const TriangleMesh& target, const std::vector<Vec3>& target_normals,
                                   const std::vector<int>& target_of);

// Over a dense vertex map, at a scale above its per-vertex noise: around each of `centres`,
// the map's differential fitted by least squares over the source vertices within `radius`
// (Euclidean edge paths) in tangent-plane coordinates; the result is the fraction of
// centres where its determinant is positive (centres where the neighbourhood maps to a
// point or a line are left out). A noisy but right map folds many single faces
// (dense_orientation_agreement then reads 0.7-0.8 for right maps and mirrors alike on
// FAUST 5k) while its neighbourhoods still keep their handedness.
double neighbourhood_orientation_agreement(const TriangleMesh& source, const std::vector<Vec3>& source_normals,
                                           const MeshTopology& source_topology, const TriangleMesh& target,
                                           const std::vector<Vec3>& target_normals,
                                           const std::vector<int>& target_of, const std::vector<int>& centres,
                                           double radius, int threads);

}  // namespace isocorr
