#include "isocorr/refinement/zoomout.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "isocorr/matching/surface_descent.h"
#include "isocorr/refinement/functional_map_fit.h"
#include "isocorr/sampling/vertex_spreading.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

using RowMatrix = SpectralRows;
// The first k columns of a basis, read in place (a copy of a 52K mesh's 200 was 40 MB of
// fresh pages for the kernel to zero).
using RowsView = SpectralRowsView;

RowMatrix gather_rows(const RowsView& basis, const std::vector<int>& rows, int k) {
  RowMatrix out(rows.size(), k);
  for (size_t i = 0; i < rows.size(); ++i) out.row(i) = basis.row(rows[i]).head(k);
  return out;
}

// Calls visit(q, scores, worker) for every row q of `queries`, scores holding |p|^2 - 2 q.p
// for every row p of `points` (the squared distance less |q|^2), by blocked matrix products
// on `threads` workers; each worker (in [0, threads)) visits its own rows.
template <class Visit>
void visit_row_scores(const RowMatrix& queries, const RowMatrix& points, int threads, const Visit& visit) {
  const Eigen::VectorXf point_norms = points.rowwise().squaredNorm();
  const int n = static_cast<int>(queries.rows());
  constexpr int kBlock = 256;
  const int blocks = (n + kBlock - 1) / kBlock;
  parallel_for(blocks, threads, [&](int block, int worker) {
    const int begin = block * kBlock, rows = std::min(kBlock, n - begin);
    // One column per query, so that each query's scores lie in contiguous memory.
    const Eigen::MatrixXf products = -2.f * (points * queries.middleRows(begin, rows).transpose());
    Eigen::VectorXf scores(points.rows());
    for (int r = 0; r < rows; ++r) {
      scores = products.col(r) + point_norms;
      visit(begin + r, scores, worker);
    }
  });
}

// For every row of `queries`, the index of the nearest row of `points` (squared Euclidean).
std::vector<int> nearest_rows(const RowMatrix& queries, const RowMatrix& points, int threads) {
  std::vector<int> nearest(queries.rows(), 0);
  visit_row_scores(queries, points, threads, [&](int q, const Eigen::VectorXf& scores, int) {
    // The least value first (a vectorised reduction), then its first position, as
    // minCoeff(&index).
    const float least = scores.minCoeff();
    const float* first = scores.data();
    const float* end = first + scores.size();
    const float* found = std::find(first, end, least);  // not found only for a NaN row
    nearest[q] = found == end ? 0 : static_cast<int>(found - first);
  });
  return nearest;
}

// Floats as integers in the same order (for numbers; -0 comes before +0), so that a value
// of given rank can be found by bisection, each step a count that vectorises.
int32_t ordered_key(float value) {
  const int32_t bits = std::bit_cast<int32_t>(value);
  return bits >= 0 ? bits : bits ^ 0x7fffffff;
}

float key_value(int32_t key) { return std::bit_cast<float>(key >= 0 ? key : key ^ 0x7fffffff); }

// The value of rank `rank` (0 = the least) among the values whose keys these are, by
// bisection over the keys' range: on a polish query's 125 chunk minima a third of the time
// of std::nth_element, and nothing to reorder.
float value_of_rank(const std::vector<int32_t>& keys, int rank) {
  int64_t low = *std::min_element(keys.begin(), keys.end());
  int64_t high = *std::max_element(keys.begin(), keys.end());
  while (low < high) {  // the answer lies in [low, high]
    const int32_t middle = static_cast<int32_t>(low + (high - low) / 2);
    int at_most = 0;
    for (const int32_t key : keys) at_most += key <= middle;
    if (at_most > rank) high = middle;
    else low = middle + 1;
  }
  return key_value(static_cast<int32_t>(low));
}

// What one worker of nearest_rows_among reuses from query to query.
struct CandidateScratch {
  std::vector<float> minima;
  std::vector<int32_t> keys;
  std::vector<std::pair<float, int>> candidates;
};

// For every row of `queries`, of the `candidates` rows of `points` nearest to it, the one of
// least cost once the extra columns count too: the squared difference of `query_extra`'s
// row and `point_extra`'s (one row per query and per point) is added. A query row with NaN
// gets index 0, as nearest_rows gives it.
std::vector<int> nearest_rows_among(const RowMatrix& queries, const RowMatrix& points, const RowMatrix& query_extra,
                                    const RowMatrix& point_extra, int candidates, int threads) {
  const int m = static_cast<int>(points.rows());
  candidates = std::clamp(candidates, 1, m);
  std::vector<int> nearest(queries.rows(), 0);
  std::vector<CandidateScratch> scratch(std::max(1, threads));
  visit_row_scores(queries, points, threads, [&](int q, const Eigen::VectorXf& scores, int worker) {
    // The candidates, the `candidates` least (score, index) pairs, without a selection over
    // every point (std::nth_element there made a 5K pair's polish growth 40% slower): the
    // candidates-th least of the chunks' minima bounds the candidates-th least score, and
    // only the chunks whose minimum lies under that bound can hold a candidate.
    constexpr int kChunk = 16;
    using Chunk = Eigen::Matrix<float, kChunk, 1>;
    const int whole_chunks = m / kChunk;
    const int chunks = (m + kChunk - 1) / kChunk;
    CandidateScratch& own = scratch[worker];
    own.minima.resize(chunks);
    own.keys.resize(chunks);
    for (int c = 0; c < whole_chunks; ++c) own.minima[c] = Eigen::Map<const Chunk>(scores.data() + c * kChunk).minCoeff();
    if (whole_chunks < chunks) own.minima[whole_chunks] = scores.tail(m - whole_chunks * kChunk).minCoeff();
    bool numbers = true;
    for (int c = 0; c < chunks; ++c) {
      numbers = numbers && !std::isnan(own.minima[c]);
      own.keys[c] = ordered_key(own.minima[c]);
    }
    if (!numbers) return;  // index 0
    const float bound = candidates <= chunks ? value_of_rank(own.keys, candidates - 1)
                                             : std::numeric_limits<float>::infinity();
    std::vector<std::pair<float, int>>& nearest_candidates = own.candidates;
    nearest_candidates.clear();
    for (int c = 0; c < chunks; ++c) {
      if (!(own.minima[c] <= bound)) continue;
      for (int j = c * kChunk; j < std::min(m, (c + 1) * kChunk); ++j)
        if (scores[j] <= bound) nearest_candidates.emplace_back(scores[j], j);
    }
    const size_t kept = std::min<size_t>(candidates, nearest_candidates.size());
    if (kept == 0) return;  // index 0
    std::nth_element(nearest_candidates.begin(), nearest_candidates.begin() + (kept - 1), nearest_candidates.end());
    float best = std::numeric_limits<float>::infinity();
    int chosen = nearest_candidates.front().second;
    for (size_t i = 0; i < kept; ++i) {
      const auto& [score, w] = nearest_candidates[i];
      const float cost = score + (query_extra.row(q) - point_extra.row(w)).squaredNorm();
      if (cost < best || (cost == best && w < chosen)) best = cost, chosen = w;
    }
    nearest[q] = chosen;
  });
  return nearest;
}

// The vertex of `rows`' mesh nearest to `query` in the embedding of the first k columns,
// by descent from `start`; `best` receives the squared distance.
int descend_in_embedding(const float* query, const RowsView& rows, int k, const MeshTopology& topology, int start,
                         float* best = nullptr) {
  // Eigen's reduction runs on whole vector registers; a plain loop's sum is one chain of
  // dependent additions (the compiler may not reorder them), four times slower at k = 100.
  const Eigen::Map<const Eigen::VectorXf> q(query, k);
  auto cost = [&](int w) { return (Eigen::Map<const Eigen::VectorXf>(rows.row(w).data(), k) - q).squaredNorm(); };
  float reached = 0;
  const int vertex = descend_to_minimum(topology, start, cost, reached);
  if (best) *best = reached;
  return vertex;
}

// Dense recovery in one direction: each `from` vertex goes to the `to` vertex whose row
// of `to_rows` is nearest to its own row of `from_rows`, found by descent on the `to` mesh
// from `start[v]`.
void recover_dense(const RowsView& from_rows, const RowsView& to_rows, const MeshTopology& to_topology,
                   const std::vector<int>& start, int threads, std::vector<int>& image, std::vector<float>& residual) {
  const int n = static_cast<int>(from_rows.rows());
  image.assign(n, 0);
  residual.assign(n, 0.f);
  parallel_for(n, threads, [&](int v, int) {
    float best = 0;
    image[v] = descend_in_embedding(from_rows.row(v).data(), to_rows, static_cast<int>(from_rows.cols()),
                                    to_topology, start[v], &best);
    residual[v] = std::sqrt(best);
  });
}

// rows * c, by chunks of rows on `threads` workers: on every vertex of a 52K mesh the
// product kept one core busy while the other waited, and on the polish's 2000 samples too.
// The chunks are fixed, so the result does not depend on the number of workers (and each
// row's sums are the whole product's: the chunks split rows, not the inner dimension).
RowMatrix times(const RowsView& rows, const Eigen::MatrixXf& c, int threads) {
  constexpr Eigen::Index kChunkRows = 1024;
  const Eigen::Index count = rows.rows();
  if (count <= kChunkRows) return rows * c;
  RowMatrix product(count, c.cols());
  const int chunks = static_cast<int>((count + kChunkRows - 1) / kChunkRows);
  parallel_for(chunks, threads, [&](int chunk, int) {
    const Eigen::Index begin = chunk * kChunkRows, size = std::min(kChunkRows, count - begin);
    product.middleRows(begin, size).noalias() = rows.middleRows(begin, size) * c;
  });
  return product;
}

// Starts for the dense recovery: each vertex starts at the image of its nearest sample.
std::vector<int> starts_from_samples(const MeshTopology& topology, int vertex_count, const std::vector<int>& samples,
                                     const std::vector<int>& sample_images) {
  std::vector<int> start = nearest_centre(topology, vertex_count, samples);
  for (int& s : start) s = sample_images[s];
  return start;
}

// One ZoomOut step on every vertex at the rows' basis size: C refitted to the current map,
// then each vertex's image moved by descent from where it is (O(V k), no all-pairs search:
// the map is already close, so the nearest row lies near the current image).
// Leaves the new C in map.c and returns the pulled rows (source rows times C).
RowMatrix refit_on_every_vertex(const RowsView& source_rows, const RowsView& target_rows,
                                const FunctionalMapFit& fit, int threads, const MeshTopology& target_topology,
                                SpectralMap& map) {
  const int k = static_cast<int>(target_rows.cols());
  map.c = fit_functional_map(source_rows, gather_rows(target_rows, map.image, k), fit);
  RowMatrix pulled = times(source_rows, map.c, threads);
  const std::vector<int> start = map.image;
  recover_dense(pulled, target_rows, target_topology, start, threads, map.image, map.residual);
  return pulled;
}

// The source's basis size against k target functions: fewer for a part (source_share < 1).
int source_size(int k, const ZoomOutOptions& options) {
  return std::max(1, std::min(k, static_cast<int>(std::lround(options.source_share * k))));
}

// A basis size no larger than either shape's basis.
int within_bases(int k, const SpectralSide& source, const SpectralSide& target) {
  return std::min<int>({k, static_cast<int>(source.basis->cols()), static_cast<int>(target.basis->cols())});
}

FunctionalMapFit fit_settings(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options,
                              int threads) {
  FunctionalMapFit fit;
  fit.source_eigenvalues = source.eigenvalues;
  fit.target_eigenvalues = target.eigenvalues;
  fit.commutativity = options.commutativity;
  fit.threads = threads;
  return fit;
}

// The reverse map from the same C: each target vertex goes to the source vertex whose
// pulled-back row (`pulled` = source rows times C) is nearest, so forward and reverse
// answer one functional map.
void recover_reverse(const SpectralSide& source, const SpectralSide& target, const RowsView& pulled,
                     const RowsView& target_rows, int threads, SpectralMap& map) {
  const int k = static_cast<int>(pulled.cols());
  const std::vector<int>& source_samples = *source.samples;
  const std::vector<int>& target_samples = *target.samples;
  const std::vector<int> nearest =
      nearest_rows(gather_rows(target_rows, target_samples, k), gather_rows(pulled, source_samples, k), threads);
  std::vector<int> reverse_images(target_samples.size());
  for (size_t i = 0; i < reverse_images.size(); ++i) reverse_images[i] = source_samples[nearest[i]];
  recover_dense(target_rows, pulled, *source.topology,
                starts_from_samples(*target.topology, static_cast<int>(target_rows.rows()), target_samples,
                                    reverse_images),
                threads, map.reverse_image, map.reverse_residual);
}

// The curvature term of the polish's pointwise cost (ZoomOutOptions::curvature_weight):
// both shapes' curvature columns (the mean curvature's, then the Gaussian curvature's when
// both sides have them) divided by the source's root mean square over its samples (evenly
// spread: an area-weighted mean), so that the two stay comparable, and the weight per unit
// of squared difference before the basis size k multiplies it: per smoothing scale, so the
// Gaussian columns add to the term (SCAPE's first 14 pairs: 0.0071 -> 0.0068; sharing the
// mean columns' weight with them instead: 0.0069).
struct CurvatureTerm {
  RowMatrix source, target;  // row-major: the descent reads one vertex's columns at a time
  double weight_per_function = 0;
};

bool has_columns(const Eigen::MatrixXf* source, const Eigen::MatrixXf* target) {
  return source && target && source->cols() > 0 && source->cols() == target->cols();
}

std::optional<CurvatureTerm> curvature_term(const SpectralSide& source, const SpectralSide& target,
                                            const ZoomOutOptions& options) {
  if (!has_curvature_polish(source, target, options)) return std::nullopt;
  const int scales = static_cast<int>(source.curvature->cols());
  const bool gaussian = has_columns(source.gaussian_curvature, target.gaussian_curvature) &&
                        source.gaussian_curvature->cols() == scales;
  const int columns = gaussian ? 2 * scales : scales;
  CurvatureTerm term;
  term.source.resize(source.curvature->rows(), columns);
  term.target.resize(target.curvature->rows(), columns);
  term.source.leftCols(scales) = *source.curvature;
  term.target.leftCols(scales) = *target.curvature;
  if (gaussian) {
    term.source.rightCols(scales) = *source.gaussian_curvature;
    term.target.rightCols(scales) = *target.gaussian_curvature;
  }
  Eigen::RowVectorXf root_mean_square = Eigen::RowVectorXf::Zero(columns);
  for (const int v : *source.samples) root_mean_square += term.source.row(v).cwiseAbs2();
  root_mean_square = (root_mean_square / static_cast<float>(source.samples->size())).cwiseSqrt().cwiseMax(1e-12f);
  term.source = term.source.array().rowwise() / root_mean_square.array();
  term.target = term.target.array().rowwise() / root_mean_square.array();
  term.weight_per_function = options.curvature_weight / scales;
  return term;
}

// The image of source vertex v whose pulled row is `query` (k columns): descent on the
// target from `start` on the spectral distance plus the weighted curvature difference;
// `spectral` receives the spectral distance there.
int descend_with_curvature(const float* query, int v, const RowsView& target_rows, int k, const CurvatureTerm& term,
                           const MeshTopology& topology, int start, float* spectral = nullptr) {
  const Eigen::Map<const Eigen::VectorXf> q(query, k);
  const float weight = static_cast<float>(term.weight_per_function * k);
  auto spectral_cost = [&](int w) { return (Eigen::Map<const Eigen::VectorXf>(target_rows.row(w).data(), k) - q).squaredNorm(); };
  auto cost = [&](int w) { return spectral_cost(w) + weight * (term.source.row(v) - term.target.row(w)).squaredNorm(); };
  float reached = 0;
  const int image = descend_to_minimum(topology, start, cost, reached);
  if (spectral) *spectral = std::sqrt(spectral_cost(image));
  return image;
}

// The curvature columns of `samples`, scaled so that their squared differences weigh as the
// curvature term does at basis size k.
RowMatrix weighted_curvature(const RowMatrix& columns, const std::vector<int>& samples, double weight) {
  RowMatrix rows(samples.size(), columns.cols());
  const float root = static_cast<float>(std::sqrt(weight));
  for (size_t i = 0; i < samples.size(); ++i) rows.row(i) = root * columns.row(samples[i]);
  return rows;
}

// The sampled iterations from basis size k_first (map.c already fitted there, or refitted
// from map.images when its size differs) up to k_end: map the source samples (nearest target
// samples in the spectral embedding), then move the images to vertex accuracy by descent on
// the target mesh (images snapped to target samples would bias C by up to a sample
// spacing), refit C with a few more basis functions.
// With `curvature` (the polish's growth, ZoomOutOptions::curvature_candidates), each image
// is the target sample of least spectral-plus-curvature cost among the curvature_candidates
// spectrally nearest, then moved by descent on the same cost.
void grow_on_samples(const SpectralSide& source, const SpectralSide& target, int k_first, int k_end,
                     const ZoomOutOptions& options, SampleMap& map, const JobControl& control,
                     const CurvatureTerm* curvature = nullptr) {
  const RowMatrix& phi_s = *source.basis;
  const RowMatrix& phi_t = *target.basis;
  const std::vector<int>& source_samples = *source.samples;
  const std::vector<int>& target_samples = *target.samples;
  const int threads = resolve_thread_count(control.threads);
  const FunctionalMapFit fit = fit_settings(source, target, options, threads);
  for (int k = k_first;; k = std::min(k + std::max(1, options.k_step), k_end)) {
    control.check_cancelled();
    const RowMatrix source_rows = gather_rows(phi_s, source_samples, source_size(k, options));
    if (map.c.cols() != k) map.c = fit_functional_map(source_rows, gather_rows(phi_t, map.images, k), fit);
    const RowMatrix queries = times(source_rows, map.c, threads);
    const RowMatrix target_rows = gather_rows(phi_t, target_samples, k);
    if (curvature) {
      const double weight = curvature->weight_per_function * k;
      const std::vector<int> nearest = nearest_rows_among(
          queries, target_rows, weighted_curvature(curvature->source, source_samples, weight),
          weighted_curvature(curvature->target, target_samples, weight), options.curvature_candidates, threads);
      parallel_for(static_cast<int>(map.images.size()), threads, [&](int i, int) {
        map.images[i] = descend_with_curvature(queries.row(i).data(), source_samples[i], phi_t, k, *curvature,
                                               *target.topology, target_samples[nearest[i]]);
      });
    } else {
      const std::vector<int> nearest = nearest_rows(queries, target_rows, threads);
      parallel_for(static_cast<int>(map.images.size()), threads, [&](int i, int) {
        map.images[i] =
            descend_in_embedding(queries.row(i).data(), phi_t, k, *target.topology, target_samples[nearest[i]]);
      });
    }
    if (k >= k_end) break;
  }
}

// curvature_iterations refits on the samples at the sampled map's basis size, each image
// moved by descent with the curvature term; leaves C fitted to the last images. No
// commutativity term: the map is right, and 2000 samples determine C at 200 functions
// (with it: the same maps, twice the time). An iteration that moves no image has reached
// the fixed point: every further one would fit the same C and descend to the same images,
// so they are skipped with the same result (centaur0 -> centaur1 settles after 8 of 10).
void sharpen_on_samples(const SpectralSide& source, const SpectralSide& target, const CurvatureTerm& term,
                        const ZoomOutOptions& options, SampleMap& sampled, const JobControl& control) {
  const int k = static_cast<int>(sampled.c.cols());
  const std::vector<int>& samples = *source.samples;
  const RowMatrix& phi_t = *target.basis;
  FunctionalMapFit fit;
  fit.threads = resolve_thread_count(control.threads);
  const RowMatrix source_rows = gather_rows(*source.basis, samples, k);
  std::vector<int> before;
  for (int iteration = 0; iteration < options.curvature_iterations; ++iteration) {
    control.check_cancelled();
    const Eigen::MatrixXf c = fit_functional_map(source_rows, gather_rows(phi_t, sampled.images, k), fit);
    const RowMatrix queries = times(source_rows, c, fit.threads);
    before = sampled.images;
    parallel_for(static_cast<int>(samples.size()), fit.threads, [&](int i, int) {
      sampled.images[i] =
          descend_with_curvature(queries.row(i).data(), samples[i], phi_t, k, term, *target.topology, sampled.images[i]);
    });
    if (sampled.images == before) {
      sampled.c = c;  // already fitted to these images
      return;
    }
  }
  sampled.c = fit_functional_map(source_rows, gather_rows(phi_t, sampled.images, k), fit);
}

// zoomout_dense's counterpart with the curvature term: every vertex's image by descent from
// its nearest sample's image, and the reverse map from the same C (spectral only: the
// rigidity polish that finishes the map recomputes it from the deformed source).
SpectralMap sharpened_dense(const SpectralSide& source, const SpectralSide& target, const CurvatureTerm& term,
                            const SampleMap& sampled, int threads, const JobControl& control) {
  const int k = static_cast<int>(sampled.c.cols());
  SpectralMap map;
  map.c = sampled.c;
  const RowsView target_rows = target.basis->leftCols(k);
  const RowMatrix pulled = times(source.basis->leftCols(k), sampled.c, threads);
  const int n = static_cast<int>(pulled.rows());
  map.image = starts_from_samples(*source.topology, n, *source.samples, sampled.images);
  map.residual.assign(n, 0.f);
  parallel_for(n, threads, [&](int v, int) {
    map.image[v] = descend_with_curvature(pulled.row(v).data(), v, target_rows, k, term, *target.topology,
                                          map.image[v], &map.residual[v]);
  });
  control.check_cancelled();
  recover_reverse(source, target, pulled, target_rows, threads, map);
  return map;
}

}  // namespace

SampleMap zoomout_on_samples(const SpectralSide& source, const SpectralSide& target,
                             const std::vector<std::pair<int, int>>& start, int k_end, const ZoomOutOptions& options,
                             const JobControl& control) {
  k_end = within_bases(k_end, source, target);
  const int k_start = std::min(options.k_start, k_end);
  if (static_cast<int>(start.size()) < k_start)
    throw InputError("spectral refinement needs at least " + std::to_string(k_start) + " starting pairs, got " +
                     std::to_string(start.size()));
  // The first functional map from the starting pairs: low frequencies only, so a start
  // with local errors still gives a smooth, global C.
  std::vector<int> from, to;
  for (const auto& [s, t] : start) from.push_back(s), to.push_back(t);
  SampleMap map;
  map.c = fit_functional_map(gather_rows(*source.basis, from, source_size(k_start, options)),
                             gather_rows(*target.basis, to, k_start),
                             fit_settings(source, target, options, resolve_thread_count(control.threads)));
  map.images.assign(source.samples->size(), 0);
  grow_on_samples(source, target, k_start, k_end, options, map, control);
  return map;
}

void continue_on_samples(const SpectralSide& source, const SpectralSide& target, int k_end,
                         const ZoomOutOptions& options, SampleMap& map, const JobControl& control) {
  k_end = within_bases(k_end, source, target);
  const int k = static_cast<int>(map.c.cols());
  if (map.images.size() != source.samples->size()) {
    // Grown on fewer samples: every sample is first mapped by the current C.
    map.images.assign(source.samples->size(), 0);
    grow_on_samples(source, target, k, k, options, map, control);
  }
  if (k >= k_end) return;
  grow_on_samples(source, target, std::min(k + std::max(1, options.k_step), k_end), k_end, options, map, control);
}

SpectralMap zoomout_dense(const SpectralSide& source, const SpectralSide& target, const SampleMap& sampled,
                          const ZoomOutOptions& options, const JobControl& control) {
  // Dense recovery at the sampled map's basis size, then `dense_iterations` refits of C on
  // every vertex (the samples fix C's low-frequency part; all vertices sharpen the last
  // basis functions).
  const int k = static_cast<int>(sampled.c.cols());
  const int threads = resolve_thread_count(control.threads);
  const FunctionalMapFit fit = fit_settings(source, target, options, threads);
  SpectralMap result;
  result.c = sampled.c;
  const RowsView source_rows = source.basis->leftCols(sampled.c.rows());
  const RowsView target_rows = target.basis->leftCols(k);
  RowMatrix pulled = times(source_rows, sampled.c, threads);  // source vertices in target coordinates
  recover_dense(pulled, target_rows, *target.topology,
                starts_from_samples(*source.topology, static_cast<int>(source_rows.rows()), *source.samples,
                                    sampled.images),
                threads, result.image, result.residual);
  for (int iteration = 0; iteration < options.dense_iterations; ++iteration) {
    control.check_cancelled();
    pulled = refit_on_every_vertex(source_rows, target_rows, fit, threads, *target.topology, result);
  }
  control.check_cancelled();
  recover_reverse(source, target, pulled, target_rows, threads, result);
  return result;
}

SpectralMap zoomout(const SpectralSide& source, const SpectralSide& target,
                    const std::vector<std::pair<int, int>>& start, const ZoomOutOptions& options,
                    const JobControl& control) {
  return zoomout_dense(source, target, zoomout_on_samples(source, target, start, options.k_end, options, control),
                       options, control);
}

std::optional<SampleMap> polish_on_samples(const SpectralSide& source, const SpectralSide& target,
                                           const ZoomOutOptions& options, const SpectralMap& map,
                                           const JobControl& control) {
  const int k = static_cast<int>(map.c.cols());
  const int k_end = std::max(k, within_bases(options.polish_k_end, source, target));
  const std::optional<CurvatureTerm> curvature = curvature_term(source, target, options);
  if (k == k_end && !curvature) return std::nullopt;
  // C is fitted afresh at k from the map's own images of the samples (map.c belongs to the
  // map before it was finished).
  SampleMap sampled;
  for (const int v : *source.samples) sampled.images.push_back(map.image[v]);
  ZoomOutOptions growth = options;
  growth.k_step = options.polish_k_step;
  const bool curvature_in_growth = curvature && options.curvature_candidates > 0;
  grow_on_samples(source, target, k, k_end, growth, sampled, control, curvature_in_growth ? &*curvature : nullptr);
  return sampled;
}

bool has_curvature_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options) {
  return options.curvature_weight > 0 && has_columns(source.curvature, target.curvature);
}

SpectralMap curvature_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options,
                             SampleMap sampled, const JobControl& control) {
  const std::optional<CurvatureTerm> curvature = curvature_term(source, target, options);
  if (!curvature) throw std::logic_error("curvature_polish: no curvature term (has_curvature_polish)");
  sharpen_on_samples(source, target, *curvature, options, sampled, control);
  return sharpened_dense(source, target, *curvature, sampled, resolve_thread_count(control.threads), control);
}

bool zoomout_polish(const SpectralSide& source, const SpectralSide& target, const ZoomOutOptions& options,
                    SpectralMap& map, const JobControl& control) {
  std::optional<SampleMap> sampled = polish_on_samples(source, target, options, map, control);
  if (!sampled) return false;
  map = has_curvature_polish(source, target, options)
            ? curvature_polish(source, target, options, std::move(*sampled), control)
            : zoomout_dense(source, target, *sampled, options, control);
  return true;
}

}  // namespace isocorr
