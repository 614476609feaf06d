// Mean curvature smoothed at a few scales: what a point's surroundings look like from
// outside. The dense choice compares it along a map because intrinsic cues cannot tell a
// human body from the same body turned by 180 degrees (left/right and front/back swapped):
// such a map keeps handedness and nearly all geodesic distances, and the heat kernel
// signature, truncated to the refinement's basis, differs by a few per cent only. Extrinsic
// detail at a few centimetres does differ: a face against the back of a head, toes against
// heels, a chest against a back. Local shape at that scale survives a change of pose
// (limbs bend at joints, not along their length), so a right map agrees with it.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// The smoothing lengths, as fractions of sqrt(surface area) (for a human about 1.3, 2.6
// and 5 cm): below the smallest the mesh's own noise dominates; above the largest the
// detail that separates front from back is averaged away.
inline const std::vector<double> kCurvatureScales = {0.01, 0.02, 0.04};

// V x scales.size(): signed mean curvature H = (M^-1 L x) . n / 2 (cotangent L, lumped M,
// n the unit vertex normal, so convex regions of an outward-oriented mesh are positive),
// times sqrt(area) (dimensionless: the same for the shape at any scale), each column
// diffused by one implicit heat step (M + t L) h = M H with t = (scale * sqrt(area))^2.
// `reference_length`, when positive, replaces sqrt(area) in both places: a part of a shape
// is compared with the whole at the whole's sqrt(area), in the part's units (a 55% part's
// own sqrt(area) is 0.74 of it, which would shrink its values and its smoothing alike).
Eigen::MatrixXf smoothed_mean_curvature(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                        const std::vector<double>& scales = kCurvatureScales,
                                        double reference_length = 0);

// Both curvatures, each V x scales.size(), smoothed alike (one factorisation per scale).
// `gaussian` is the Gaussian curvature K times the area (dimensionless): the angle defect
// (2 pi less the corner angles around a vertex, pi less them at a boundary vertex) is
// M K, diffused as M H is above. The mean curvature alone cannot tell a cylinder's side from
// a cap or a saddle of the same H; K can (a kneecap against the shin beside it), and it too
// survives a change of pose away from the joints. On a sphere K area = 4 pi everywhere;
// on any closed genus-0 surface its area-weighted mean is 4 pi (Gauss-Bonnet).
struct SmoothedCurvature {
  Eigen::MatrixXf mean;
  Eigen::MatrixXf gaussian;
};
SmoothedCurvature smoothed_mean_and_gaussian_curvature(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                                       const std::vector<double>& scales = kCurvatureScales,
                                                       double reference_length = 0);

// How much two shapes' smoothed curvatures differ at corresponding points: for each scale
// (column), sum |h_S(a) - h_T(b)| over sum (|h_S(a)| + |h_T(b)|) over the (a, b) pairs, then
// the mean over scales. 0 for a map between identical shapes; at most 1.
double curvature_disagreement(const Eigen::MatrixXf& source_curvature, const Eigen::MatrixXf& target_curvature,
                              const std::vector<std::pair<int, int>>& pairs);

}  // namespace isocorr
