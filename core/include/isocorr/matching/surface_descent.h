// Greedy descent of a per-vertex cost over a mesh: how the engine finds, on the other
// surface, the vertex whose distances to the anchors best agree (the d_iso minimum).
#pragma once

#include <array>
#include <type_traits>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// The vertices a descent has already costed. None of them can beat the best cost any
// more (each was at least the best when costed, and the best only falls), so they are not
// costed again: a step's ring shares about half its vertices with the last one, and the
// final two-ring look costs 36 vertices of which about 12 are new. A small open-addressing
// table; once half full it stops remembering (vertices are then costed again: the same
// result, more work).
class CostedVertices {
 public:
  CostedVertices() { slots_.fill(-1); }
  // False where `v` was costed already; otherwise remembers it and returns true.
  bool first_time(int v) {
    if (used_ >= kSlots / 2) return true;
    for (unsigned i = (static_cast<unsigned>(v) * 2654435761u) >> (32 - kBits);; i = (i + 1) & (kSlots - 1)) {
      if (slots_[i] == v) return false;
      if (slots_[i] < 0) {
        slots_[i] = v;
        ++used_;
        return true;
      }
    }
  }

 private:
  static constexpr int kBits = 8;
  static constexpr unsigned kSlots = 1u << kBits;
  std::array<int, kSlots> slots_;
  unsigned used_ = 0;
};

// What one cost evaluation costs: for a dear one (distances to many anchors) the descent
// remembers which vertices it costed; for a cheap one (a 3D distance) that bookkeeping
// would cost more than it saves.
enum class CostPrice { kCheap, kDear };

// Moves to the best one-ring neighbour while the cost drops, looking one ring further
// before giving up, and returns the local minimum reached from `start` (its cost in `best`).
// The price changes the work only, never the result.
template <CostPrice price = CostPrice::kCheap, typename Cost>
int descend_to_minimum(const MeshTopology& topology, int start, Cost cost, float& best) {
  struct Nothing {};
  std::conditional_t<price == CostPrice::kDear, CostedVertices, Nothing> costed;
  int w = start;
  if constexpr (price == CostPrice::kDear) costed.first_time(w);
  best = cost(w);
  int next = -1;
  auto try_vertex = [&](int u) {
    if constexpr (price == CostPrice::kDear)
      if (!costed.first_time(u)) return;
    const float c = cost(u);
    if (c < best) best = c, next = u;
  };
  for (;;) {
    next = -1;
    for (const int* u = topology.neighbours_begin(w); u != topology.neighbours_end(w); ++u) try_vertex(*u);
    if (next < 0) {
      for (const int* u = topology.neighbours_begin(w); u != topology.neighbours_end(w); ++u)
        for (const int* z = topology.neighbours_begin(*u); z != topology.neighbours_end(*u); ++z) try_vertex(*z);
    }
    if (next < 0) return w;
    w = next;
  }
}

}  // namespace isocorr
