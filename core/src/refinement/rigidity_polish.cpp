#include "isocorr/refinement/rigidity_polish.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "isocorr/matching/surface_descent.h"
#include "isocorr/spectral/laplace_beltrami.h"
#include "isocorr/util/error.h"
#include "isocorr/util/ldlt_row_solve.h"
#include "isocorr/util/parallel.h"
#include "mirrored_segments.h"
#include "rigidity_rings.h"

namespace isocorr {
namespace {

// Fit weights of the three stages, in units of mass / (mean edge)^2, where 1 weighs a
// vertex's fit about as much as its ring's rigidity. A loose fit first lets rigidity
// move the surface; the last, firm one settles every vertex onto the target. Measured on
// SCAPE 000 -> 004 (D_grd 0.0157 before): 0.0134 / 0.0131 / 0.0130 after the three stages
// of 50 iterations; starting looser (0.01 or 0.03) lets the source leave the target and
// snap to wrong places (0.0190).
constexpr double kFitWeights[] = {0.3, 1.0, 3.0};

// The same rotation, moved towards from the ring's previous one: the iteration of Müller et
// al. 2016 ("A robust method to extract the rotational part of deformations") maximises
// tr(R^T covariance^T) and, started from a nearby rotation, needs a few cheap steps where
// an SVD per vertex would cost a third of the polish (52K vertices, 60 iterations).
void update_rotation(const Eigen::Matrix3d& covariance, Eigen::Quaterniond& rotation) {
  constexpr int kSteps = 3;
  const Eigen::Matrix3d a = covariance.transpose();
  for (int step = 0; step < kSteps; ++step) {
    const Eigen::Matrix3d r = rotation.toRotationMatrix();
    const Eigen::Vector3d omega = (r.col(0).cross(a.col(0)) + r.col(1).cross(a.col(1)) + r.col(2).cross(a.col(2))) /
                                  (std::abs(r.col(0).dot(a.col(0)) + r.col(1).dot(a.col(1)) + r.col(2).dot(a.col(2))) +
                                   1e-12);
    const double angle = omega.norm();
    if (angle < 1e-9) return;
    rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle)) * rotation;
    rotation.normalize();
  }
}

// The vertex of `mesh` nearest to `point` in space, by descent over `topology` from `start`.
int nearest_by_descent(const TriangleMesh& mesh, const MeshTopology& topology, const Vec3& point, int start,
                       float& squared_distance) {
  auto cost = [&](int w) { return static_cast<float>((mesh.vertices[w] - point).squaredNorm()); };
  return descend_to_minimum(topology, start, cost, squared_distance);
}

}  // namespace

// The pair's part of the polish: the source's rings, scaled to the target, and one factored
// system per fit weight.
struct RigiditySystem {
  Rings rings;
  Eigen::VectorXd mass;                 // scaled lumped mass
  std::vector<double> lambdas;          // fit weight of each stage
  std::vector<std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>> solvers;  // L + lambda M
};

namespace {

// One deformation's state between iterations: where the source is, where each vertex's
// nearest-vertex search starts, and the last local step's rotations and fit points.
struct Deformation {
  DeformedPoints& deformed;
  std::vector<int>& image;
  DeformedPoints fit_points, rhs;
  std::vector<Eigen::Quaterniond> rotation;
  std::vector<Eigen::Matrix3d> rotation_matrix;
  bool first_iteration = true;

  Deformation(DeformedPoints& deformed, std::vector<int>& image)
      : deformed(deformed), image(image), fit_points(deformed.rows(), 3), rhs(deformed.rows(), 3),
        rotation(deformed.rows()), rotation_matrix(deformed.rows()) {}
};

// Local step: each ring's best rotation; and each vertex's fit point, the tangent plane of
// the target at the nearest vertex (a plane, not the vertex, so that the fit does not hold
// the surface where it is: sliding along the target is free to first order).
void fit_rotations_and_planes(const Rings& rings, const PreprocessedShape& target, Deformation& state, int workers) {
  const TriangleMesh& to = target.mesh();
  const MeshTopology& to_topology = target.geodesics().topology();
  const std::vector<Vec3>& to_normals = target.normals();
  parallel_for(static_cast<int>(state.deformed.rows()), workers, [&](int v, int) {
    const Eigen::Matrix3d covariance = ring_covariance(rings, state.deformed, v);
    if (state.first_iteration) state.rotation[v] = Eigen::Quaterniond(best_rotation(covariance));
    else update_rotation(covariance, state.rotation[v]);
    state.rotation_matrix[v] = state.rotation[v].toRotationMatrix();
    const Vec3 y = state.deformed.row(v).transpose();
    float squared = 0;
    state.image[v] = nearest_by_descent(to, to_topology, y, state.image[v], squared);
    const Vec3& p = to.vertices[state.image[v]];
    const Vec3& normal = to_normals[state.image[v]];
    state.fit_points.row(v) = (y - normal * normal.dot(y - p)).transpose();
  });
}

// Global step: (L + lambda M) Y = sum_j w (R_i + R_j) rest_ij / 2 + lambda M fit.
void solve_positions(const RigiditySystem& system, size_t stage, Deformation& state, int workers) {
  const Rings& rings = system.rings;
  const double lambda = system.lambdas[stage];
  parallel_for(static_cast<int>(state.deformed.rows()), workers, [&](int v, int) {
    Vec3 b = lambda * system.mass(v) * state.fit_points.row(v).transpose();
    for (int e = rings.offsets[v]; e < rings.offsets[v + 1]; ++e) {
      const RingEdge& ring = rings.edges[e];
      b += 0.5 * ring.weight * (state.rotation_matrix[v] + state.rotation_matrix[ring.to]) * ring.rest;
    }
    state.rhs.row(v) = b.transpose();
  });
  solve_rows_in_place(*system.solvers[stage], state.rhs);
  state.deformed = state.rhs;
}

// The energy a deformation ends at: rigidity plus the fit of weight `lambda`.
double deformation_energy(const RigiditySystem& system, double lambda, const Deformation& state, int workers) {
  const Rings& rings = system.rings;
  const DeformedPoints& deformed = state.deformed;
  const int n = static_cast<int>(deformed.rows());
  std::vector<double> energy(n, 0.0);
  parallel_for(n, workers, [&](int v, int) {
    const Vec3 y = deformed.row(v).transpose();
    double e = lambda * system.mass(v) * (y - state.fit_points.row(v).transpose()).squaredNorm();
    for (int k = rings.offsets[v]; k < rings.offsets[v + 1]; ++k) {
      const RingEdge& ring = rings.edges[k];
      e += ring.weight * ((y - deformed.row(ring.to).transpose()) - state.rotation_matrix[v] * ring.rest).squaredNorm();
    }
    energy[v] = e;
  });
  double total = 0;
  for (const double e : energy) total += e;  // in order: the same sum for any thread count
  return total;
}

// The three stages from `deformed` (and `image`, where each vertex's nearest-vertex search
// starts) on `workers` threads; returns the energy they end at, rigidity plus the last
// stage's fit.
double deform(const RigiditySystem& system, const PreprocessedShape& target, int iterations,
              DeformedPoints& deformed, std::vector<int>& image, int workers, const JobControl& control) {
  Deformation state(deformed, image);
  double lambda = 0;
  for (size_t stage = 0; stage < system.lambdas.size(); ++stage) {
    lambda = system.lambdas[stage];
    for (int iteration = 0; iteration < iterations; ++iteration) {
      control.check_cancelled();
      fit_rotations_and_planes(system.rings, target, state, workers);
      solve_positions(system, stage, state, workers);
      state.first_iteration = false;
    }
  }
  return deformation_energy(system, lambda, state, workers);
}

// The source placed at its images.
DeformedPoints at_images(const TriangleMesh& target, const std::vector<int>& image) {
  DeformedPoints deformed(image.size(), 3);
  for (size_t v = 0; v < image.size(); ++v) deformed.row(v) = target.vertices[image[v]].transpose();
  return deformed;
}

// The maps from the deformed source: each source vertex to the target vertex nearest its
// deformed position, and (unless map.reverse_image is empty) each target vertex to the
// source vertex whose deformed position is nearest, both by descent from their images.
void read_out(const PreprocessedShape& source, const PreprocessedShape& target, const DeformedPoints& deformed,
              SpectralMap& map, int threads) {
  const TriangleMesh& to = target.mesh();
  const MeshTopology& to_topology = target.geodesics().topology();
  const double inverse_diameter = 1.0 / target.diameter();
  map.residual.assign(deformed.rows(), 0.f);
  parallel_for(static_cast<int>(deformed.rows()), threads, [&](int v, int) {
    float squared = 0;
    map.image[v] = nearest_by_descent(to, to_topology, deformed.row(v).transpose(), map.image[v], squared);
    map.residual[v] = static_cast<float>(std::sqrt(squared) * inverse_diameter);
  });
  if (map.reverse_image.empty()) return;
  const MeshTopology& from_topology = source.geodesics().topology();
  const int m = to.num_vertices();
  map.reverse_residual.assign(m, 0.f);
  parallel_for(m, threads, [&](int w, int) {
    auto cost = [&](int v) { return static_cast<float>((deformed.row(v).transpose() - to.vertices[w]).squaredNorm()); };
    float squared = 0;
    map.reverse_image[w] = descend_to_minimum(from_topology, map.reverse_image[w], cost, squared);
    map.reverse_residual[w] = static_cast<float>(std::sqrt(squared) * inverse_diameter);
  });
}

void check_fits(const PreprocessedShape& source, const PreprocessedShape& target, const SpectralMap& map) {
  if (static_cast<int>(map.image.size()) != source.mesh().num_vertices() ||
      (!map.reverse_image.empty() && static_cast<int>(map.reverse_image.size()) != target.mesh().num_vertices()))
    throw std::logic_error("rigidity_polish: the map does not fit the shapes");
}

}  // namespace

RigidityPolish::RigidityPolish(const PreprocessedShape& source, const PreprocessedShape& target,
                               const RigidityOptions& options)
    : RigidityPolish(source, target, options, std::sqrt(target.area() / source.area())) {}

RigidityPolish::RigidityPolish(const PreprocessedShape& source, const PreprocessedShape& target,
                               const RigidityOptions& options, double source_to_target)
    : source_(source), target_(target), options_(options) {
  if (options.iterations <= 0) return;
  if (!(source_to_target > 0) || !std::isfinite(source_to_target))
    throw std::logic_error("RigidityPolish: the scale must be positive");
  const double scale = source_to_target;  // source lengths to target lengths
  auto system = std::make_unique<RigiditySystem>();
  system->rings = build_rings(source.mesh(), scale);
  system->mass = lumped_mass(source.mesh()) * (scale * scale);
  const double edge = source.mean_edge() * scale;
  const int n = source.mesh().num_vertices();
  for (const double weight : kFitWeights) {
    const double lambda = weight / (edge * edge);
    Eigen::SparseMatrix<double> matrix = system->rings.laplacian;
    for (int v = 0; v < n; ++v) matrix.coeffRef(v, v) += lambda * system->mass(v);
    auto solver = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(matrix);
    if (solver->info() != Eigen::Success) throw InputError("rigidity polish: the source's rigidity system is singular");
    system->lambdas.push_back(lambda);
    system->solvers.push_back(std::move(solver));
  }
  system_ = std::move(system);
}

RigidityPolish::~RigidityPolish() = default;

MirrorRepair rigidity_polish(const PreprocessedShape& source, const PreprocessedShape& target,
                             const RigidityOptions& options, SpectralMap& map, const JobControl& control) {
  return RigidityPolish(source, target, options).apply(map, control);
}

MirrorRepair RigidityPolish::apply(SpectralMap& map, const JobControl& control) const {
  if (options_.mirror_repair) return polish_with_mirror_repair(map, control, control.threads);
  polish(map, control, control.threads);
  return {};
}

MirrorRepair RigidityPolish::unfold_mirrors(SpectralMap& map) const {
  if (!system_) return {};
  DeformedPoints deformed = at_images(target_.mesh(), map.image);
  const MirroredSegments segments = unfold_mirrored_segments(source_, target_, system_->rings, map.image, deformed);
  return {segments.reversed_vertices, segments.segments, false};  // no polish here, so no energy to compare
}

void RigidityPolish::polish(SpectralMap& map, const JobControl& control, int thread_count) const {
  if (!system_) return;
  check_fits(source_, target_, map);
  const int threads = resolve_thread_count(thread_count);
  DeformedPoints deformed = at_images(target_.mesh(), map.image);
  deform(*system_, target_, options_.iterations, deformed, map.image, threads, control);
  control.check_cancelled();
  read_out(source_, target_, deformed, map, threads);
}

MirrorRepair RigidityPolish::polish_with_mirror_repair(SpectralMap& map, const JobControl& control,
                                                       int thread_count) const {
  if (!system_) return {};
  check_fits(source_, target_, map);
  const int threads = resolve_thread_count(thread_count);
  std::vector<int>& image = map.image;
  DeformedPoints deformed = at_images(target_.mesh(), image);
  // Both starts are polished and the lower energy wins: the unfolded segments must earn
  // their place against the fold the polish would otherwise settle in.
  DeformedPoints unfolded = deformed;
  std::vector<int> unfolded_image = image;
  const MirroredSegments segments =
      unfold_mirrored_segments(source_, target_, system_->rings, unfolded_image, unfolded);
  MirrorRepair repair;
  repair.reversed_vertices = segments.reversed_vertices;
  repair.segments = segments.segments;
  // The two polishes side by side, the workers shared out: each one's sparse solves run on
  // one thread and left the other core idle (michael0 -> michael1's last finishing).
  double energies[2] = {0, 0};
  parallel_for_sharing(segments.segments > 0 ? 2 : 1, threads, [&](int which, int shared) {
    const int iterations = options_.iterations;
    energies[which] = which == 0 ? deform(*system_, target_, iterations, deformed, image, shared, control)
                                 : deform(*system_, target_, iterations, unfolded, unfolded_image, shared, control);
  });
  if (segments.segments > 0 && energies[1] < energies[0]) {
    deformed.swap(unfolded);
    image.swap(unfolded_image);
    repair.kept = true;
  }
  control.check_cancelled();
  read_out(source_, target_, deformed, map, threads);
  return repair;
}

}  // namespace isocorr
