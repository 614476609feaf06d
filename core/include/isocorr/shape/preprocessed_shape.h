// Everything the matcher needs from one mesh, computed once and shared by every job that
// uses the mesh (the service caches these by mesh digest).
//
// Two faces, as for every expensive step: `PreprocessedShape::build` does the set-up
// (cleaning, geodesics, saliency, the sample hierarchy and its distance fields); a match
// is then a stream of cheap queries against it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "isocorr/geodesic/fast_marching.h"
#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/sampling/saliency.h"
#include "isocorr/util/progress.h"

namespace isocorr {

struct PreprocessOptions {
  SaliencyOptions saliency;
  CleaningOptions cleaning;
  double level0_radius = 0.2;   // level-0 sampling radius, fraction of the geodesic diameter
  double level_shrink = 0.66;   // radius factor from one level to the next: ~250 source
                                // samples at K1 = 4, as in the paper
  int decision_level = 4;       // K1 (paper: 4, about 250 matched vertices)
  int max_level0_samples = 9;   // level-0 samples kept per mesh (M' <= this)
  // Laplace-Beltrami eigenpairs kept for refinement (0 = none). The refinement runs on the
  // first 100; the rest serve the chosen map's polish (zoomout.h). They cost time: per
  // mesh 0.24 -> 0.70 s at 5K vertices, 0.74 -> 1.8 s at 12.5K, 3.4 -> 7.1 s at 52K
  // (block_lanczos.h; Spectra's Lanczos took 0.79, 2.4 and 19 s for 200).
  int spectral_basis = 200;
  int spectral_samples = 2000;  // evenly spread vertices the refinement iterates on
  int spectral_cells = 0;       // meshes with more vertices solve the eigenproblem on this
                                // many cells (reduced_laplace_basis.h); 0 = never

  // Cache key part: two option sets with equal keys give identical preprocessing.
  std::string key() const;
};

class PreprocessedShape {
 public:
  // Cleans `input` and computes everything. Throws InputError for unusable meshes and
  // Cancelled when `control` asks.
  static std::shared_ptr<const PreprocessedShape> build(const TriangleMesh& input,
                                                        const PreprocessOptions& options,
                                                        const JobControl& control = {});

  const CleanMesh& clean() const { return clean_; }
  const TriangleMesh& mesh() const { return clean_.mesh; }
  const FastMarching& geodesics() const { return *geodesics_; }
  const Saliency& saliency() const { return saliency_; }
  const std::vector<Vec3>& normals() const { return normals_; }
  double diameter() const { return diameter_; }
  double area() const { return area_; }
  double mean_edge() const { return mean_edge_; }
  const PreprocessOptions& options() const { return options_; }

  // The sample hierarchy. Sample i sits at vertex sample_vertex(i) and was accepted at
  // schedule step sample_step(i): step 0 is level 0, step j >= 1 belongs to half-level j
  // (radius level0_radius * level_shrink^(j/2)). Sources match the samples of steps <= 2k
  // at level k, targets offer those of steps <= 2k+1 (the paper's M' > M margin).
  int num_samples() const { return static_cast<int>(sample_vertices_.size()); }
  int sample_vertex(int i) const { return sample_vertices_[i]; }
  int sample_step(int i) const { return sample_steps_[i]; }
  int num_level0_samples() const;
  // Geodesic distance from sample i to vertex v, divided by the diameter.
  float field(int i, int v) const { return fields_[static_cast<size_t>(i) * mesh().num_vertices() + v]; }
  const float* field_row(int i) const { return fields_.data() + static_cast<size_t>(i) * mesh().num_vertices(); }
  // field(i, sample_vertex(j)), laid out by sample: tracking compares each candidate image
  // with its parent's, and a row of this table is read where the fields would be read at
  // scattered vertices (TOSCA 5k: 192 tracked maps of about 300 samples).
  float sample_field(int i, int j) const { return sample_fields_[static_cast<size_t>(i) * num_samples() + j]; }

  // The Laplace-Beltrami basis (V x spectral_basis, mass-orthonormal times sqrt(area)) and
  // the vertices refinement iterates on; empty when spectral_basis = 0.
  using SpectralBasis = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const SpectralBasis& spectral_basis() const { return spectral_basis_; }
  const std::vector<int>& spectral_samples() const { return spectral_samples_; }
  // Its eigenvalues times the area (scale-invariant, like the basis), ascending.
  const Eigen::VectorXf& spectral_eigenvalues() const { return spectral_eigenvalues_; }
  // Mean curvature smoothed at kCurvatureScales (mean_curvature.h), V x scales; empty
  // when spectral_basis = 0 (only the dense choice reads it).
  const Eigen::MatrixXf& smoothed_curvature() const { return smoothed_curvature_; }
  // Gaussian curvature times the area, smoothed at the same scales, V x scales; empty when
  // spectral_basis = 0 (only the curvature polish reads it, the dense choice does not).
  const Eigen::MatrixXf& smoothed_gaussian_curvature() const { return smoothed_gaussian_curvature_; }

  size_t memory_bytes() const;

 private:
  PreprocessedShape() = default;
  // Steps of build: the cleaned mesh, its topology, geodesics, normals, area and mean
  // edge; then, after the sample hierarchy, each sample's field and the diameter.
  void clean_and_measure(const TriangleMesh& input, const JobControl& control);
  void compute_sample_fields(int threads, const JobControl& control);

  PreprocessOptions options_;
  CleanMesh clean_;
  std::unique_ptr<MeshTopology> topology_;
  std::unique_ptr<FastMarching> geodesics_;
  Saliency saliency_;
  std::vector<Vec3> normals_;
  double diameter_ = 0, area_ = 0, mean_edge_ = 0;
  std::vector<int> sample_vertices_, sample_steps_;
  std::vector<float> fields_;
  std::vector<float> sample_fields_;  // num_samples() squared
  SpectralBasis spectral_basis_;
  std::vector<int> spectral_samples_;
  Eigen::VectorXf spectral_eigenvalues_;
  Eigen::MatrixXf smoothed_curvature_;
  Eigen::MatrixXf smoothed_gaussian_curvature_;
};

}  // namespace isocorr
