// Validation and repair of loaded meshes. Every step is sort-, union-find- or k-d-tree based
// so that a 60K-vertex mesh is cleaned in milliseconds. Until the final compaction, vertices
// keep their input numbering, so messages name vertices as the file does.
#include "isocorr/mesh/mesh_cleaning.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <tuple>

#include <Eigen/Geometry>

#include "isocorr/util/error.h"
#include "isocorr/mesh/coordinate_normalisation.h"
#include "isocorr/util/kd_tree.h"
#include "isocorr/util/radius_components.h"
#include "isocorr/util/union_find.h"

namespace isocorr {

namespace {

template <class... Parts>
std::string cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

std::string count_of(long long n, const char* singular, const char* plural) {
  return cat(n, ' ', n == 1 ? singular : plural);
}

double bounding_diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0.0;
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

void validate_input(const TriangleMesh& input) {
  for (int v = 0; v < input.num_vertices(); ++v)
    if (!input.vertices[v].allFinite()) throw InputError(cat("vertex ", v, " has a non-finite coordinate"));
  for (int f = 0; f < input.num_faces(); ++f)
    for (int v : input.faces[f])
      if (v < 0 || v >= input.num_vertices())
        throw InputError(
            cat("face ", f, " refers to vertex ", v, " but the mesh has ", input.num_vertices(), " vertices"));
  if (input.faces.empty()) throw InputError("the mesh has no faces");
}

bool is_degenerate(const std::vector<Vec3>& points, const Face& f) {
  if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return true;
  const Vec3 e0 = points[f[1]] - points[f[0]], e1 = points[f[2]] - points[f[0]], e2 = points[f[2]] - points[f[1]];
  const double longest_squared = std::max({e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()});
  // Collinear up to rounding: twice the area is negligible next to the longest edge squared.
  return e0.cross(e1).norm() <= 1e-12 * longest_squared;
}

// Items grouped by a vertex index in [0, num_vertices) (a counting sort, linear), then ordered
// within each group by `less`. Items are made twice from their sources (once counted, once
// placed) rather than copied, so the sorted array is the only one held: cleaning's peak
// memory is a few of these arrays, a bounded multiple of the file size.
template <class Item, class Make, class Key, class Less>
std::vector<Item> grouped_by_vertex(size_t sources, int num_vertices, const Make& make, const Key& key,
                                    const Less& less) {
  std::vector<size_t> start(static_cast<size_t>(num_vertices) + 1, 0);
  for (size_t i = 0; i < sources; ++i) ++start[key(make(i)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<Item> sorted(start.back());
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (size_t i = 0; i < sources; ++i) {
    const Item item = make(i);
    sorted[next[key(item)]++] = item;
  }
  for (int v = 0; v < num_vertices; ++v)
    if (start[v + 1] - start[v] > 1) std::sort(sorted.begin() + start[v], sorted.begin() + start[v + 1], less);
  return sorted;
}

// One corner's edge of a face, keyed by its endpoints in increasing order.
struct EdgeUse {
  int low, high, face, corner;
};

// All edge uses, grouped by undirected edge and in face order within a group. Held as use
// numbers (3 face + corner, four bytes each) and expanded where read.
class SortedEdgeUses {
 public:
  SortedEdgeUses(const std::vector<Face>& faces, int num_vertices) : faces_(faces) {
    order_ = grouped_by_vertex<int>(
        3 * faces.size(), num_vertices, [](size_t i) { return static_cast<int>(i); },
        [&](int i) { return (*this)(i).low; },
        [&](int a, int b) { return std::pair((*this)(a).high, a) < std::pair((*this)(b).high, b); });
  }
  size_t size() const { return order_.size(); }
  EdgeUse operator[](size_t k) const { return (*this)(order_[k]); }

 private:
  EdgeUse operator()(int use) const {
    const int f = use / 3, k = use % 3;
    const auto [low, high] = std::minmax(faces_[f][k], faces_[f][(k + 1) % 3]);
    return {low, high, f, k};
  }

  const std::vector<Face>& faces_;
  std::vector<int> order_;
};

// End of the group of uses of the same edge as uses[begin].
size_t edge_run_end(const SortedEdgeUses& uses, size_t begin) {
  size_t end = begin + 1;
  while (end < uses.size() && uses[end].low == uses[begin].low && uses[end].high == uses[begin].high) ++end;
  return end;
}

// Vertices that may be welded: unused ones and those on a boundary edge, where seams and
// triangle soups leave copies. Coincident vertices inside closed fans are distinct points
// where a surface touches itself (several FAUST remeshes have them); welding those would
// create non-manifold edges.
std::vector<int> open_vertices(const TriangleMesh& mesh) {
  std::vector<bool> open(mesh.vertices.size(), true);
  for (const Face& f : mesh.faces)
    for (int v : f) open[v] = false;
  const SortedEdgeUses uses(mesh.faces, mesh.num_vertices());
  for (size_t begin = 0, end = 0; begin < uses.size(); begin = end) {
    end = edge_run_end(uses, begin);
    if (end - begin == 1) open[uses[begin].low] = open[uses[begin].high] = true;
  }
  std::vector<int> ids;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (open[v]) ids.push_back(v);
  return ids;
}


// Faces across each edge (-1 on the boundary) and whether the neighbour runs the shared edge
// in the same direction, i.e. disagrees in orientation.
struct FaceAdjacency {
  std::vector<std::array<int, 3>> neighbour;
  std::vector<std::array<bool, 3>> same_direction;
};

FaceAdjacency build_adjacency(const std::vector<Face>& faces, int num_vertices) {
  const SortedEdgeUses uses(faces, num_vertices);
  FaceAdjacency adjacency{std::vector<std::array<int, 3>>(faces.size(), {-1, -1, -1}),
                          std::vector<std::array<bool, 3>>(faces.size(), {false, false, false})};
  auto runs_forward = [&](const EdgeUse& u) { return faces[u.face][u.corner] < faces[u.face][(u.corner + 1) % 3]; };
  for (size_t begin = 0, end = 0; begin < uses.size(); begin = end) {
    end = edge_run_end(uses, begin);
    if (end - begin > 2)
      throw InputError(cat("non-manifold edge between vertices ", uses[begin].low, " and ", uses[begin].high,
                           " (shared by ", end - begin,
                           " faces); the engine needs a manifold surface"));
    if (end - begin < 2) continue;
    const EdgeUse a = uses[begin], b = uses[begin + 1];
    const bool same = runs_forward(a) == runs_forward(b);
    adjacency.neighbour[a.face][a.corner] = b.face, adjacency.same_direction[a.face][a.corner] = same;
    adjacency.neighbour[b.face][b.corner] = a.face, adjacency.same_direction[b.face][b.corner] = same;
  }
  return adjacency;
}

void flip(Face& f) { std::swap(f[1], f[2]); }

// Welded faces that are not degenerate (repeated corner or zero area).
std::vector<Face> drop_degenerate_faces(const std::vector<Face>& input, const std::vector<Vec3>& points,
                                        const std::vector<int>& rep, long long& dropped) {
  std::vector<Face> faces;
  faces.reserve(input.size());
  for (const Face& f : input) {
    const Face welded = {rep[f[0]], rep[f[1]], rep[f[2]]};
    if (is_degenerate(points, welded)) ++dropped;
    else faces.push_back(welded);
  }
  return faces;
}

// Drops later copies of a face with the same vertex set; returns how many.
long long drop_duplicate_faces(std::vector<Face>& faces, int num_vertices) {
  // Face numbers ordered by their corner-sorted triples, ties by number, bring copies together
  // with the first copy leading; four bytes a face, the triples made again where compared.
  auto triple = [&](int f) {
    Face corners = faces[f];
    std::sort(corners.begin(), corners.end());
    return corners;
  };
  const std::vector<int> order = grouped_by_vertex<int>(
      faces.size(), num_vertices, [](size_t f) { return static_cast<int>(f); },
      [&](int f) { return *std::min_element(faces[f].begin(), faces[f].end()); },
      [&](int a, int b) { return std::pair(triple(a), a) < std::pair(triple(b), b); });
  std::vector<bool> duplicate(faces.size(), false);
  for (size_t i = 1; i < order.size(); ++i) duplicate[order[i]] = triple(order[i]) == triple(order[i - 1]);
  const size_t before = faces.size();
  size_t kept = 0;
  for (size_t f = 0; f < before; ++f)
    if (!duplicate[f]) faces[kept++] = faces[f];
  faces.resize(kept);
  return static_cast<long long>(before - kept);
}

struct NonManifoldRepair {
  long long edges = 0;  // edges that had more than two faces
  long long faces = 0;  // faces dropped
};

// Keeps two faces on every edge shared by more than two: the pair that best continues the
// surface, i.e. whose unit normals agree best once the two are oriented consistently (run
// the edge in opposite directions). With the edge as axis, each face is a half-plane leaving
// it along d (the unit direction from the edge to its third corner, perpendicular to the
// edge); for such a pair the normals are e x d1 and -e x d2, whose dot product is -d1.d2.
// So the kept pair is the one whose half-planes are closest to opposite (dihedral angle
// closest to 180 degrees): a stray fin on a surface is dropped, of two crossing sheets one
// is kept whole. The input winding is ignored, orientation is fixed afterwards.
//
// One pass suffices: dropping faces only ever lowers the face count of other edges, so an
// edge visited with at most two faces left never gets more, and each visit considers only
// the faces not dropped yet. Per edge with k faces the best pair is found in O(k log k): the
// half-planes sorted by angle about the edge, the one most nearly opposite to each is a
// neighbour of its angle + 180 degrees. Faces keep their order; vertices, components and
// patches the dropping leaves behind are handled by the steps after this one.
NonManifoldRepair repair_non_manifold_edges(std::vector<Face>& faces, const std::vector<Vec3>& points,
                                            int num_vertices) {
  const SortedEdgeUses uses(faces, num_vertices);
  std::vector<char> dropped(faces.size(), 0);
  NonManifoldRepair repair;
  struct HalfPlane {
    double angle;     // about the edge, in [-pi, pi]
    int face;
    Vec3 direction;   // unit, perpendicular to the edge, towards the third corner
  };
  std::vector<HalfPlane> fins;
  for (size_t begin = 0, end = 0; begin < uses.size(); begin = end) {
    end = edge_run_end(uses, begin);
    if (end - begin <= 2) continue;
    ++repair.edges;
    const Vec3& origin = points[uses[begin].low];
    const Vec3 axis = (points[uses[begin].high] - origin).normalized();
    const Vec3 u = axis.unitOrthogonal(), v = axis.cross(u);
    fins.clear();
    for (size_t i = begin; i < end; ++i) {
      if (dropped[uses[i].face]) continue;
      const Vec3& apex = points[faces[uses[i].face][(uses[i].corner + 2) % 3]];
      Vec3 d = apex - origin;
      d = (d - d.dot(axis) * axis).normalized();  // non-zero: degenerate faces are gone
      fins.push_back({std::atan2(d.dot(v), d.dot(u)), uses[i].face, d});
    }
    const int k = static_cast<int>(fins.size());
    if (k <= 2) continue;
    std::sort(fins.begin(), fins.end(),
              [](const HalfPlane& a, const HalfPlane& b) { return std::tie(a.angle, a.face) < std::tie(b.angle, b.face); });
    int best_a = -1, best_b = -1;
    double best_agreement = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < k; ++i) {
      double opposite = fins[i].angle + std::numbers::pi;
      if (opposite > std::numbers::pi) opposite -= 2 * std::numbers::pi;
      const int at = static_cast<int>(
          std::lower_bound(fins.begin(), fins.end(), opposite,
                           [](const HalfPlane& fin, double angle) { return fin.angle < angle; }) -
          fins.begin());
      for (const int j : {at % k, (at + k - 1) % k}) {
        if (j == i) continue;
        const double agreement = -fins[i].direction.dot(fins[j].direction);
        if (agreement > best_agreement) best_agreement = agreement, best_a = i, best_b = j;
      }
    }
    for (int i = 0; i < k; ++i)
      if (i != best_a && i != best_b) dropped[fins[i].face] = 1, ++repair.faces;
  }
  if (repair.faces > 0) {
    size_t kept = 0;
    for (size_t f = 0; f < faces.size(); ++f)
      if (!dropped[f]) faces[kept++] = faces[f];
    faces.resize(kept);
  }
  return repair;
}

struct ComponentChoice {
  int count = 0;            // connected components, through shared vertices
  double kept_share = 1.0;  // fraction of the area in the one kept
};

ComponentChoice keep_largest_component(std::vector<Face>& faces, const std::vector<Vec3>& points, int num_vertices,
                                       bool allowed) {
  UnionFind components(num_vertices);
  for (const Face& f : faces) components.unite(f[0], f[1]), components.unite(f[0], f[2]);
  std::vector<double> area(num_vertices, 0.0);  // indexed by component root
  double total = 0.0;
  for (const Face& f : faces) {
    const double face_area = 0.5 * (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]).norm();
    area[components.find(f[0])] += face_area;
    total += face_area;
  }
  ComponentChoice choice;
  std::vector<bool> counted(num_vertices, false);
  int largest = -1;
  for (const Face& f : faces) {
    const int root = components.find(f[0]);
    if (counted[root]) continue;
    counted[root] = true;
    ++choice.count;
    if (largest < 0 || area[root] > area[largest]) largest = root;
  }
  if (choice.count <= 1) return choice;
  if (!allowed) throw InputError(cat("the mesh has ", choice.count, " connected components; only one is allowed"));
  choice.kept_share = total > 0 ? area[largest] / total : 1.0;
  std::erase_if(faces, [&](const Face& f) { return components.find(f[0]) != largest; });
  return choice;
}

// Edge-connected patches of faces, in breadth-first order.
struct Patches {
  std::vector<int> patch_of;  // per face
  int count = 0;
};

// Flips faces to agree with the face they were reached from across a shared edge, then flips
// back whichever side is the minority of its patch. Returns the faces changed.
long long orient_consistently(std::vector<Face>& faces, int num_vertices, Patches& patches) {
  const FaceAdjacency adjacency = build_adjacency(faces, num_vertices);
  const int num_faces = static_cast<int>(faces.size());
  patches.patch_of.assign(num_faces, -1);
  std::vector<char> flipped(num_faces, 0);
  std::vector<int> order;
  order.reserve(num_faces);
  long long changed = 0;
  for (int seed = 0; seed < num_faces; ++seed) {
    if (patches.patch_of[seed] >= 0) continue;
    const size_t begin = order.size();
    patches.patch_of[seed] = patches.count;
    order.push_back(seed);
    for (size_t next = begin; next < order.size(); ++next) {
      const int f = order[next];
      for (int k = 0; k < 3; ++k) {
        const int g = adjacency.neighbour[f][k];
        if (g < 0) continue;
        const char wanted = flipped[f] ^ static_cast<char>(adjacency.same_direction[f][k]);
        if (patches.patch_of[g] < 0) {
          patches.patch_of[g] = patches.count, flipped[g] = wanted;
          order.push_back(g);
        } else if (flipped[g] != wanted) {
          throw InputError(cat("the surface is non-orientable (like a Moebius strip): its faces cannot agree on an "
                               "orientation around the edge between vertices ", faces[f][k], " and ",
                               faces[f][(k + 1) % 3]));
        }
      }
    }
    const auto members = std::span(order).subspan(begin);
    const long long count = std::count_if(members.begin(), members.end(), [&](int f) { return flipped[f] != 0; });
    if (2 * count > static_cast<long long>(members.size()))
      for (int f : members) flipped[f] ^= 1;
    changed += std::min<long long>(count, members.size() - count);
    ++patches.count;
  }
  for (int f = 0; f < num_faces; ++f)
    if (flipped[f]) flip(faces[f]);
  return changed;
}

// Flips every patch that encloses negative signed volume. Measured about the centroid (exact
// for closed patches); near-zero volumes (flat open sheets) are left alone. Returns patches flipped.
int orient_outward(std::vector<Face>& faces, const Patches& patches, const std::vector<Vec3>& points, double diagonal) {
  Vec3 centroid = Vec3::Zero();
  for (const Face& f : faces) centroid += points[f[0]] + points[f[1]] + points[f[2]];
  centroid /= 3.0 * static_cast<double>(faces.size());
  std::vector<double> volume(patches.count, 0.0);
  for (size_t f = 0; f < faces.size(); ++f) {
    const Vec3 a = points[faces[f][0]] - centroid, b = points[faces[f][1]] - centroid;
    volume[patches.patch_of[f]] += a.dot(b.cross(points[faces[f][2]] - centroid)) / 6.0;
  }
  const double negligible = 1e-12 * std::pow(diagonal, 3);
  for (size_t f = 0; f < faces.size(); ++f)
    if (volume[patches.patch_of[f]] < -negligible) flip(faces[f]);
  return static_cast<int>(std::count_if(volume.begin(), volume.end(), [&](double v) { return v < -negligible; }));
}

// For every kept face (welded numbering), the first input face with the same corners once
// welded, and where its corners are among the kept face's. Input faces are ordered by their
// welded, sorted triples (four bytes a face, triples made again where compared) and each
// kept face is looked up there.
std::vector<CleanMesh::InputFace> input_faces_of(const std::vector<Face>& input, const std::vector<int>& rep,
                                                 const std::vector<Face>& kept) {
  auto welded_triple = [&](const Face& f) {
    Face corners = {rep[f[0]], rep[f[1]], rep[f[2]]};
    std::sort(corners.begin(), corners.end());
    return corners;
  };
  std::vector<int> order(input.size());
  for (size_t f = 0; f < order.size(); ++f) order[f] = static_cast<int>(f);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::pair(welded_triple(input[a]), a) < std::pair(welded_triple(input[b]), b);
  });
  std::vector<CleanMesh::InputFace> origins(kept.size());
  for (size_t f = 0; f < kept.size(); ++f) {
    Face corners = kept[f];
    std::sort(corners.begin(), corners.end());
    const auto found = std::lower_bound(order.begin(), order.end(), corners,
                                        [&](int g, const Face& key) { return welded_triple(input[g]) < key; });
    if (found == order.end() || welded_triple(input[*found]) != corners) continue;
    origins[f].face = *found;
    for (int k = 0; k < 3; ++k)
      origins[f].clean_corner[k] = static_cast<unsigned char>(
          std::find(kept[f].begin(), kept[f].end(), rep[input[*found][k]]) - kept[f].begin());
  }
  return origins;
}

}  // namespace

CleanMesh clean_mesh(const TriangleMesh& input, const CleaningOptions& options) {
  validate_input(input);
  CleanMesh result;
  std::vector<Vec3> points = input.vertices;
  result.normalisation = normalise_coordinates(points);
  const int num_input = input.num_vertices();
  std::vector<std::string>& repairs = result.repairs;

  // Until compaction, faces use input numbering with every welded group as its first vertex.
  // Tolerances below double precision of the extent mean exact matching.
  const double diagonal = bounding_diagonal(points);
  double tolerance = options.weld_tolerance * diagonal;
  if (!(tolerance > 1e-15 * diagonal)) tolerance = 0.0;
  // rep[v]: the smallest-numbered vertex within `tolerance` of v (transitively) among the
  // open vertices; every other vertex represents itself.
  const std::vector<int> rep = radius_components(points, open_vertices(input), tolerance);
  long long welded = 0;
  for (int v = 0; v < num_input; ++v) welded += rep[v] != v;
  if (welded > 0) repairs.push_back(cat("welded ", count_of(welded, "duplicate vertex", "duplicate vertices")));

  long long degenerate = 0;
  std::vector<Face> faces = drop_degenerate_faces(input.faces, points, rep, degenerate);
  if (degenerate > 0)
    repairs.push_back(cat("dropped ", count_of(degenerate, "degenerate face", "degenerate faces"),
                          " (repeated corners or zero area)"));
  if (const long long duplicates = drop_duplicate_faces(faces, num_input); duplicates > 0)
    repairs.push_back(cat("dropped ", count_of(duplicates, "duplicate face", "duplicate faces")));
  if (faces.empty()) throw InputError("no faces are left after dropping degenerate ones");
  // Before `referenced`, components and orientation: vertices only the dropped faces used
  // are then reported and mapped like any unused vertex, split-off pieces go with the
  // smaller components, and the adjacency below sees at most two faces per edge.
  // Non-manifold vertices (fans meeting only at a vertex) need no repair: orientation
  // spreads across edges only, components join through vertices, and MeshTopology and the
  // engine use one-rings as unordered lists, never walking around a vertex fan by fan.
  if (options.repair_non_manifold_edges)
    if (const NonManifoldRepair repaired = repair_non_manifold_edges(faces, points, num_input); repaired.faces > 0)
      repairs.push_back(cat("dropped ", count_of(repaired.faces, "face", "faces"), " on ",
                            count_of(repaired.edges, "non-manifold edge", "non-manifold edges"),
                            " (more than two faces per edge)"));
  std::vector<bool> referenced(num_input, false);
  for (const Face& f : faces)
    for (int v : f) referenced[v] = true;

  const ComponentChoice components = keep_largest_component(faces, points, num_input, options.keep_largest_component);
  Patches patches;
  if (const long long changed = orient_consistently(faces, num_input, patches); changed > 0)
    repairs.push_back(cat("re-oriented ", count_of(changed, "face", "faces"), " to agree with their neighbours"));
  if (const int turned = orient_outward(faces, patches, points, diagonal); turned == patches.count)
    repairs.push_back("flipped all faces to point outward");
  else if (turned > 0)
    repairs.push_back(cat("flipped ", turned, " of ", patches.count, " surface patches to point outward"));

  // Compact in input order; every other input vertex maps to its welded copy or the nearest kept vertex.
  std::vector<int> clean_index(num_input, -1);
  for (const Face& f : faces)
    for (int v : f) clean_index[v] = 0;
  for (int v = 0; v < num_input; ++v)
    if (clean_index[v] == 0) {
      clean_index[v] = result.mesh.num_vertices();
      result.mesh.vertices.push_back(points[v]);
      result.clean_to_input.push_back(v);
    }
  result.mesh.faces.reserve(faces.size());
  for (const Face& f : faces) result.mesh.faces.push_back({clean_index[f[0]], clean_index[f[1]], clean_index[f[2]]});
  result.clean_face_origins = input_faces_of(input.faces, rep, faces);

  std::optional<KdTree> kept_tree;  // built only when some vertex was dropped
  result.input_to_clean.resize(num_input);
  long long unreferenced = 0, outside = 0;
  for (int v = 0; v < num_input; ++v) {
    result.input_to_clean[v] = clean_index[rep[v]];
    if (result.input_to_clean[v] >= 0) continue;
    if (!kept_tree) kept_tree.emplace(points, result.clean_to_input);
    result.input_to_clean[v] = clean_index[kept_tree->nearest(points[v])];
    ++(referenced[rep[v]] ? outside : unreferenced);
  }
  if (unreferenced > 0)
    repairs.push_back(cat("dropped ", count_of(unreferenced, "vertex", "vertices"),
                          " used by no face; each maps to its nearest kept vertex"));
  if (components.count > 1) {
    char share[16];
    std::snprintf(share, sizeof share, "%.1f%%", 100.0 * components.kept_share);
    repairs.push_back(cat("kept the largest of ", components.count, " connected components (", share, " of the area); ",
                          count_of(outside, "vertex", "vertices"),
                          outside == 1 ? " outside it maps" : " outside it map", " to their nearest kept vertex"));
  }
  return result;
}

void check_matchable(const CleanMesh& clean) {
  if (clean.mesh.num_vertices() < kMinMatchableVertices)
    throw InputError(cat("the mesh has only ", clean.mesh.num_vertices(), " usable vertices; at least ",
                         kMinMatchableVertices, " are needed to match"));
}

}  // namespace isocorr
