// Spectral upsampling of a map (ZoomOut, Melzi et al. 2019), in its sampling variant: the
// functional map is grown from k_start to k_end basis functions on a few thousand evenly
// spread vertices per mesh, and the dense pointwise map is recovered once at the end.
//
// Notation (docs/algorithm.md): Phi_S, Phi_T are the eigenbases (rows
// are vertices). A map T: source -> target pulls target functions back to the source, so
// Phi_S C ~ Phi_T[T(.)] with C = argmin ||Phi_S[samples] C - Phi_T[T(samples)]|| (k x k);
// a source vertex v then maps to the target vertex whose row of Phi_T is nearest to row v
// of Phi_S C.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/util/progress.h"

namespace isocorr {

struct ZoomOutOptions {
  int k_start = 20;  // basis size of the first functional map: low frequencies only, so a
                     // start with local errors still gives a smooth, global C
  int k_end = 100;   // last basis size (at most the basis the shapes hold)
  int k_step = 5;    // growth per iteration (the paper: 1-5)
  int dense_iterations = 1;  // refits of C on every vertex after the sampled iterations
  // zoomout_polish continues the chosen, finished map (right at k_end functions) on the
  // samples up to polish_k_end functions, in steps of polish_k_step: the higher frequencies
  // sharpen it. Figures, and growth on every vertex instead: docs/decisions.md, "Spectral
  // polish of the chosen map".
  int polish_k_end = 200;
  int polish_k_step = 5;
  // Weight of the Laplacian commutativity term in every fit (functional_map_fit.h; 0 = off):
  // the functional map of an isometry commutes with the Laplacians, and without the term
  // the coarse stages pull even a map started from the ground truth away from it. Figures
  // and cost: docs/decisions.md, "ZoomOut refinement".
  double commutativity = 10;
  // The curvature polish (curvature_polish), after the basis growth: weight of the
  // extrinsic term (0 = off) and its iterations on the samples. See that function for why
  // and what it gains.
  double curvature_weight = 3;
  int curvature_iterations = 10;
  // The curvature term in the polish's basis growth too (0 = growth on the spectral
  // embedding alone): each sample's image is the target sample of least spectral plus
  // curvature cost among this many spectrally nearest (32 of 2000 samples: a patch of
  // about 1.6% of the area). Room to turn back a limb turned about its own axis, which
  // the last refits' descent cannot undo, but not to leave it for another limb. Figures:
  // docs/decisions.md, "Curvature polish".
  int curvature_candidates = 32;
  // Source functions per target function: 1 between complete shapes; a part's share of the
  // whole's area for a part (partial_refinement.h): a part's i-th eigenvalue is about the
  // whole's (i / share)-th (Weyl's law), so C is fitted as share*k by k. No commutativity
  // term then (its spectra are not one shape's).
  double source_share = 1;
};

// One side of the problem: a basis (V x K, row-major floats for fast row distances), the
// mesh topology for the dense recovery, and the vertices the iterations run on.
struct SpectralSide {
  const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>* basis = nullptr;
  const MeshTopology* topology = nullptr;
  const std::vector<int>* samples = nullptr;
  const Eigen::VectorXf* eigenvalues = nullptr;  // of the basis; without them no commutativity term
  // Smoothed mean curvature (V x scales, mean_curvature.h); without it no curvature polish.
  const Eigen::MatrixXf* curvature = nullptr;
  // Smoothed Gaussian curvature, the same scales; joins the polish's term when both sides have it.
  const Eigen::MatrixXf* gaussian_curvature = nullptr;
};

struct SpectralMap {
  std::vector<int> image;       // every source vertex -> target vertex
  std::vector<float> residual;  // spectral distance of each pair (lower = better agreement)
  std::vector<int> reverse_image;  // every target vertex -> source vertex, from the same C
  std::vector<float> reverse_residual;
  Eigen::MatrixXf c;            // the last functional map (source functions x target functions)
};

// The sampled stage's state: the functional map at its current basis size (k = c.cols())
// and the image (a target vertex) of each of the source's spectral samples.
struct SampleMap {
  Eigen::MatrixXf c;
  std::vector<int> images;
};

// The sampled stage from a map given on a few source vertices (`start`: (source vertex,
// target vertex) pairs, at least k_start of them, e.g. a tracked map's sample pairs): C
// fitted at k_start, grown by k_step up to k_end (at most the bases' size). Cheap at a small
// k_end (no vertex beyond the samples is touched): a way to see where a start leads.
SampleMap zoomout_on_samples(const SpectralSide& source, const SpectralSide& target,
                             const std::vector<std::pair<int, int>>& start, int k_end, const ZoomOutOptions& options,
                             const JobControl& control = {});

// Grows a sampled map on from its basis size to k_end; the same as having asked
// zoomout_on_samples for k_end at once. A map grown on other samples (fewer, say) is first
// carried to source.samples by its C at its basis size.
void continue_on_samples(const SpectralSide& source, const SpectralSide& target, int k_end,
                         const ZoomOutOptions& options, SampleMap& map, const JobControl& control = {});

// The dense map from a sampled one, at its basis size: every vertex's image, then
// options.dense_iterations refits on every vertex, and the reverse map from the last C.
SpectralMap zoomout_dense(const SpectralSide& source, const SpectralSide& target, const SampleMap& sampled,
                          const ZoomOutOptions& options, const JobControl& control = {});

// Refines a map given on a few source vertices into a dense map: zoomout_on_samples up to
// options.k_end, then zoomout_dense. Deterministic for given inputs; `control` is checked
// between iterations.
SpectralMap zoomout(const SpectralSide& source, const SpectralSide& target,
                    const std::vector<std::pair<int, int>>& start, const ZoomOutOptions& options,
                    const JobControl& control = {});

// The spectral polish of a refined (finished) map, in two stages that refine_and_choose
// times apart; zoomout_polish runs both.
//
// The first stage continues the map to a larger basis: ZoomOut's sampled iterations from
// the map's images of the source samples, the basis grown from the map's size by
// options.polish_k_step up to options.polish_k_end (at most the bases' size). With
// has_curvature_polish and options.curvature_candidates, the curvature term already picks
// the images during this growth (among that many spectrally nearest target samples).
// Returns the sampled map at that size, or nothing when there is neither a basis to grow
// nor a curvature term. Its dense map is then zoomout_dense's, or the curvature polish's.
std::optional<SampleMap> polish_on_samples(const SpectralSide& source, const SpectralSide& target,
                                           const ZoomOutOptions& options, const SpectralMap& map,
                                           const JobControl& control = {});

// Whether the curvature polish runs: options.curvature_weight > 0 and both sides' curvature.
bool has_curvature_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options);

// The second stage, the curvature polish (with has_curvature_polish), in place of
// zoomout_dense at the sampled map's size. Why: on scans of people the truth is no more
// isometric than the maps ZoomOut converges to (SCAPE: mean geodesic distortion of the
// ground truth 0.009-0.029 of the diameter, of our maps 0.008-0.028), so intrinsic refits
// leave smooth slides of a centimetre or two along the body; local shape seen from outside
// (smoothed curvature: a knee, a shoulder blade, a nose) does not slide with them. So
// the refits go on with the pointwise cost |Phi_S C - Phi_T|^2 + w |h_S - h_T|^2, h the
// mean and (when both sides have it) Gaussian curvature columns, each divided by its root
// mean square over the source's samples, and w = curvature_weight * k / scales, scales the
// number of smoothing scales (each of the k spectral coordinates and each normalised
// curvature has unit mean square; the Gaussian columns add to the mean ones' weight, not
// share it): curvature_iterations refits on the samples,
// then every vertex once, each image moved by descent. The reverse map comes from the same C.
SpectralMap curvature_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options,
                             SampleMap sampled, const JobControl& control = {});

// Both stages: polish_on_samples, then curvature_polish or, without a curvature term,
// zoomout_dense (forward and reverse maps from the last C). Returns whether the map
// changed (false: no growth asked and no curvature term).
bool zoomout_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options,
                    SpectralMap& map, const JobControl& control = {});

}  // namespace isocorr
