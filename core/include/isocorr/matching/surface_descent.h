// Greedy descent of a per-vertex cost over a mesh: how the engine finds, on the other
// surface, the vertex whose distances to the anchors best agree (the d_iso minimum).
#pragma once

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// Moves to the best one-ring neighbour while the cost drops, looking one ring further
// before giving up, and returns the local minimum reached from `start` (its cost in `best`).
template <typename Cost>
int descend_to_minimum(const MeshTopology& topology, int start, Cost cost, float& best) {
  int w = start;
  best = cost(w);
  for (;;) {
    int next = -1;
    for (const int* u = topology.neighbours_begin(w); u != topology.neighbours_end(w); ++u) {
      const float c = cost(*u);
      if (c < best) best = c, next = *u;
    }
    if (next < 0) {
      for (const int* u = topology.neighbours_begin(w); u != topology.neighbours_end(w); ++u)
        for (const int* z = topology.neighbours_begin(*u); z != topology.neighbours_end(*u); ++z) {
          const float c = cost(*z);
          if (c < best) best = c, next = *z;
        }
    }
    if (next < 0) return w;
    w = next;
  }
}

}  // namespace isocorr
