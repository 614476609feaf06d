// UV transfer through a precise map, with the seam rule of uv_transfer.h.
#include "isocorr/transfer/uv_transfer.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "isocorr/util/error.h"
#include "isocorr/util/union_find.h"

namespace isocorr {

namespace {

using Uv = std::array<double, 2>;
using Weights = Eigen::Vector3d;

// A chart grown for one triangle stops at this many faces, so that a map flinging a
// triangle's corners across the surface costs bounded time (its UVs are poor either way).
// A chart spans about ten times the target faces under the triangle: exact up to a target
// about seven times finer than the source in edge length. 4096 took 52 s for a random map of
// 20k triangles onto 80k, 512 takes 6 s.
constexpr size_t kMaxChartFaces = 512;

// Each vt index's first index with the same coordinates, so that edges join on equal UVs.
std::vector<int> canonical_uvs(const std::vector<Uv>& uvs) {
  std::vector<int> order(uvs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return uvs[a] < uvs[b]; });
  std::vector<int> canonical(uvs.size());
  for (size_t k = 0; k < order.size(); ++k)
    canonical[order[k]] = k > 0 && uvs[order[k]] == uvs[order[k - 1]] ? canonical[order[k - 1]] : order[k];
  return canonical;
}

// Faces that share an edge, and whether they give both its ends the same UVs (joined).
struct FacePair {
  int first, second;
  bool joined;
};

// Every pair of faces across an edge (a chain through the faces of a non-manifold edge,
// faces with the same UVs on it next to each other).
std::vector<FacePair> edge_face_pairs(const TriangleMesh& mesh, const CornerAttributes& corners,
                                      const std::vector<int>& canonical) {
  struct Edge {
    int low, high, low_uv, high_uv, face;
    auto key() const { return std::tie(low, high, low_uv, high_uv, face); }
  };
  std::vector<Edge> edges;
  edges.reserve(3 * mesh.faces.size());
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      const int index_a = corners.face_uvs[f][k], index_b = corners.face_uvs[f][(k + 1) % 3];
      const int uv_a = index_a < 0 ? -1 : canonical[index_a], uv_b = index_b < 0 ? -1 : canonical[index_b];
      if (a < b) edges.push_back({a, b, uv_a, uv_b, f});
      else edges.push_back({b, a, uv_b, uv_a, f});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key() < y.key(); });
  std::vector<FacePair> pairs;
  for (size_t i = 1; i < edges.size(); ++i) {
    const Edge &x = edges[i - 1], &y = edges[i];
    if (x.low != y.low || x.high != y.high || x.face == y.face) continue;
    // A corner without a UV joins nothing.
    const bool joined = x.low_uv == y.low_uv && x.high_uv == y.high_uv && x.low_uv >= 0 && x.high_uv >= 0;
    pairs.push_back({x.face, y.face, joined});
  }
  return pairs;
}

void require_uvs(const TriangleMesh& mesh, const CornerAttributes& corners) {
  check_corner_attributes(mesh, corners);
  if (corners.face_uvs.empty()) throw InputError("the textured mesh has no texture coordinates");
}

// Where a source vertex lands: its target face, position and UV there.
struct Landing {
  int face = -1;
  Vec3 position = Vec3::Zero();
  Uv uv{0, 0};
};

// The nearest point of a chart to a landed point.
struct ChartPoint {
  double distance = std::numeric_limits<double>::infinity();
  int face = -1;
  Weights weights = Weights(1, 0, 0);
};

class UvTransfer {
 public:
  explicit UvTransfer(const TexturedMesh& target)
      : mesh_(target.mesh),
        corners_(target.corners),
        neighbours_(mesh_.faces.size()),
        stamp_(mesh_.faces.size(), -1) {
    for (const FacePair& pair : edge_face_pairs(mesh_, corners_, canonical_uvs(corners_.uvs))) {
      neighbours_[pair.first].push_back({pair.second, pair.joined});
      neighbours_[pair.second].push_back({pair.first, pair.joined});
    }
    Vec3 low = Vec3::Zero(), high = Vec3::Zero();
    if (!mesh_.vertices.empty()) low = high = mesh_.vertices.front();
    for (const Vec3& p : mesh_.vertices) low = low.cwiseMin(p), high = high.cwiseMax(p);
    // Float weights place a point to about 1e-7 of the mesh's size: a point landed on a
    // shared edge or vertex is this close to both faces.
    tolerance_ = 1e-6 * std::max((high - low).norm(), 1e-300);
  }

  Uv uv_at(int face, const Weights& weights) const {
    Uv uv{0, 0};
    for (int k = 0; k < 3; ++k) {
      const int index = corners_.face_uvs[face][k];
      if (index < 0) continue;
      uv[0] += weights[k] * corners_.uvs[index][0];
      uv[1] += weights[k] * corners_.uvs[index][1];
    }
    return uv;
  }

  // The UVs of one source triangle's corners (the seam rule of uv_transfer.h); returns the
  // target face whose material the triangle takes (-1: no corner matched).
  int triangle_uvs(const std::array<const Landing*, 3>& corners, std::array<Uv, 3>& uvs) {
    std::array<int, 4> starts{-1, -1, -1, -1};  // the corners' faces, then the centre's
    Vec3 centre = Vec3::Zero();
    int matched = 0, first = -1;
    for (int k = 0; k < 3; ++k) {
      uvs[k] = corners[k]->uv;
      if (corners[k]->face < 0) continue;
      starts[k] = corners[k]->face;
      centre += corners[k]->position;
      ++matched;
      if (first < 0) first = k;
    }
    if (matched == 0) return -1;
    centre /= matched;
    double extent = 0;
    for (int k = 0; k < 3; ++k)
      if (starts[k] >= 0) extent = std::max(extent, (corners[k]->position - centre).norm());

    // The face the triangle's centre lands on: near the corners' faces unless the map
    // stretches the triangle over many target faces. When every corner's face is in the
    // centre's chart the triangle crosses no seam and each corner keeps its own UV.
    grow(starts[first], centre, extent + tolerance_, false);
    starts[3] = nearest_in_chart(centre).face;
    grow(starts[3], centre, extent + tolerance_, true);
    bool smooth = true;
    for (int k = 0; k < 3; ++k)
      smooth = smooth && (starts[k] < 0 || std::find(chart_.begin(), chart_.end(), starts[k]) != chart_.end());
    if (smooth) return starts[3];

    // The chart holding the most landed points wins; ties go to the one nearest the centre,
    // then to the first.
    struct Candidate {
      int held = -1;
      double centre_distance = 0;
      int material_face = -1;
      std::array<ChartPoint, 3> nearest;
      std::array<bool, 3> own{};
    } best, candidate;
    for (int s = 0; s < 4; ++s) {
      if (starts[s] < 0 || std::find(starts.begin(), starts.begin() + s, starts[s]) != starts.begin() + s) continue;
      grow(starts[s], centre, 2 * extent + tolerance_, true);
      candidate.held = 0;
      for (int k = 0; k < 3; ++k) {
        if (starts[k] < 0) continue;
        candidate.nearest[k] = nearest_in_chart(corners[k]->position);
        candidate.own[k] = std::find(chart_.begin(), chart_.end(), starts[k]) != chart_.end();
        candidate.held += candidate.own[k] || candidate.nearest[k].distance <= tolerance_;
      }
      const ChartPoint middle = nearest_in_chart(centre);
      candidate.centre_distance = middle.distance;
      candidate.material_face = middle.face;
      if (candidate.held > best.held ||
          (candidate.held == best.held && candidate.centre_distance < best.centre_distance - tolerance_))
        best = candidate;
    }
    // A corner whose own face is in the winning chart keeps its UV; the others move onto it.
    for (int k = 0; k < 3; ++k)
      if (starts[k] >= 0 && !best.own[k]) uvs[k] = uv_at(best.nearest[k].face, best.nearest[k].weights);
    return best.material_face;
  }

 private:
  struct Neighbour {
    int face;
    bool joined;
  };

  // Into chart_: the faces reached from `start` across edges (only joined ones if
  // `joined_only`: then it is the part of a UV island around start) whose closest points lie
  // within `radius` of `centre`.
  void grow(int start, const Vec3& centre, double radius, bool joined_only) {
    ++chart_number_;
    chart_.assign(1, start);
    stamp_[start] = chart_number_;
    for (size_t next = 0; next < chart_.size() && chart_.size() < kMaxChartFaces; ++next)
      for (const Neighbour& neighbour : neighbours_[chart_[next]]) {
        if (stamp_[neighbour.face] == chart_number_ || (joined_only && !neighbour.joined)) continue;
        stamp_[neighbour.face] = chart_number_;
        if (closest_point(neighbour.face, centre).distance <= radius) chart_.push_back(neighbour.face);
      }
  }

  ChartPoint closest_point(int face, const Vec3& p) const {
    const Face& f = mesh_.faces[face];
    const Weights w = nearest_on_triangle(p, mesh_.vertices[f[0]], mesh_.vertices[f[1]], mesh_.vertices[f[2]]);
    const Vec3 q = w[0] * mesh_.vertices[f[0]] + w[1] * mesh_.vertices[f[1]] + w[2] * mesh_.vertices[f[2]];
    return {(q - p).norm(), face, w};
  }

  ChartPoint nearest_in_chart(const Vec3& p) const {
    ChartPoint best;
    for (int face : chart_) {
      const ChartPoint candidate = closest_point(face, p);
      if (candidate.distance < best.distance) best = candidate;
    }
    return best;
  }

  const TriangleMesh& mesh_;
  const CornerAttributes& corners_;
  std::vector<std::vector<Neighbour>> neighbours_;
  double tolerance_ = 0;
  // The chart being grown, and which faces it has looked at (by chart number, never cleared).
  std::vector<int> chart_;
  std::vector<int> stamp_;
  int chart_number_ = 0;
};

}  // namespace

std::vector<int> uv_islands(const TriangleMesh& mesh, const CornerAttributes& corners) {
  require_uvs(mesh, corners);
  UnionFind islands(mesh.num_faces());
  for (const FacePair& pair : edge_face_pairs(mesh, corners, canonical_uvs(corners.uvs)))
    if (pair.joined) islands.unite(pair.first, pair.second);
  // The union-find's roots are each island's first face, so numbering by root is by first face.
  std::vector<int> number(mesh.faces.size(), -1), island(mesh.faces.size());
  int count = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int root = islands.find(f);
    if (number[root] < 0) number[root] = count++;
    island[f] = number[root];
  }
  return island;
}

CornerAttributes transfer_uvs(const TriangleMesh& source, const TexturedMesh& target, const PreciseMap& map) {
  require_uvs(target.mesh, target.corners);
  if (static_cast<long long>(map.size()) != source.num_vertices())
    throw InputError("the precise map has " + std::to_string(map.size()) + " points but the source mesh " +
                     std::to_string(source.num_vertices()) + " vertices");
  UvTransfer transfer(target);
  std::vector<Landing> landings(map.size());
  for (size_t v = 0; v < map.size(); ++v) {
    const SurfacePoint& point = map[v];
    if (point.face < -1 || point.face >= target.mesh.num_faces())
      throw InputError("the precise map sends vertex " + std::to_string(v) + " to face " +
                       std::to_string(point.face) + " of a mesh of " + std::to_string(target.mesh.num_faces()) +
                       " faces");
    if (point.face < 0) continue;
    const Weights weights(point.weights[0], point.weights[1], point.weights[2]);
    landings[v] = {point.face, surface_position(target.mesh, point), transfer.uv_at(point.face, weights)};
  }

  CornerAttributes out;
  out.material_library = target.corners.material_library;
  out.materials = target.corners.materials;
  out.face_uvs.resize(source.faces.size());
  const bool materials = !target.corners.face_materials.empty();
  if (materials) out.face_materials.assign(source.faces.size(), -1);
  // Corners of one vertex with the same UV share one vt.
  std::map<std::tuple<int, double, double>, int> numbers;
  for (int f = 0; f < source.num_faces(); ++f) {
    const Face& face = source.faces[f];
    std::array<Uv, 3> uvs;
    const int material_face = transfer.triangle_uvs({&landings[face[0]], &landings[face[1]], &landings[face[2]]}, uvs);
    if (materials && material_face >= 0) out.face_materials[f] = target.corners.face_materials[material_face];
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = numbers.try_emplace({face[k], uvs[k][0], uvs[k][1]}, static_cast<int>(out.uvs.size()));
      if (added) out.uvs.push_back(uvs[k]);
      out.face_uvs[f][k] = it->second;
    }
  }
  if (std::all_of(out.face_materials.begin(), out.face_materials.end(), [](int m) { return m < 0; }))
    out.face_materials.clear();
  return out;
}

}  // namespace isocorr
