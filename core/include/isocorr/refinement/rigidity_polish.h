// The last stage of every refined map: nearly isometric shapes deform locally rigidly.
//
// A spectral map is fitted in a truncated basis; on shapes that are only nearly isometric
// (real bodies in two poses) its fixpoint slides the surface by about a percent of the
// diameter between the well-anchored extremities, and each vertex's image carries the
// nearest-neighbour noise of the embedding. Measured on SCAPE 000 -> 004: the true map's
// as-rigid-as-possible energy is 0.42 (per unit area), the refined map's 7.2.
//
// This stage deforms the source, scaled to the target's area, onto the target by
// non-rigid ICP with an as-rigid-as-possible regulariser (Sorkine & Alexa 2007): it starts
// from the map's images, alternates best local rotations, nearest target vertices (by
// descent from the current image, so a vertex never jumps to another part of the body that
// happens to lie close in space) and one linear solve that balances rigidity against a fit
// to the target's tangent plane at those vertices, with the fit's weight raised in three
// stages. The map then sends each vertex to the target vertex nearest its deformed
// position, and each target vertex to the source vertex whose deformed position is
// nearest. Extrinsic, but only through local shape: a pose change does not affect it.
//
// A fold is a local minimum of that energy: a stretch of a limb that the map sends
// mirrored stays mirrored. So the polish with the mirror repair (polish_with_mirror_repair)
// also starts from the map with such segments placed again (mirrored_segments.h in the
// sources) and keeps whichever end state has the lower energy.
#pragma once

#include <memory>

#include "isocorr/refinement/zoomout.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

struct RigidityOptions {
  // Iterations per fit weight (three weights); 0 = no polish. The global slide shrinks
  // slowly (long-wavelength modes are soft under a local rigidity energy), so more
  // iterations keep helping a little.
  int iterations = 20;
  // Also polish from the map with its mirrored limb segments placed again, and keep the
  // lower-energy result (see above).
  bool mirror_repair = true;
};

// What the mirror repair of one polish found and did.
struct MirrorRepair {
  int reversed_vertices = 0;  // vertices whose one-ring the map reverses
  int segments = 0;           // mirrored segments held at two or more ends, placed again
  bool kept = false;          // the polish from the placed segments ended at the lower energy
};

// The pair's rings and factored systems (rigidity_polish.cpp).
struct RigiditySystem;

// The polish for one pair of shapes: the source's rings and the three factored systems
// depend on the pair only, so a match that polishes several candidates builds them once.
class RigidityPolish {
 public:
  RigidityPolish(const PreprocessedShape& source, const PreprocessedShape& target, const RigidityOptions& options);
  // For a source that is only a part of the target's shape: their areas do not give the
  // scale, so `source_to_target` (target length per source length, 1 / kappa) does.
  RigidityPolish(const PreprocessedShape& source, const PreprocessedShape& target, const RigidityOptions& options,
                 double source_to_target);
  ~RigidityPolish();

  // Replaces map.image / residual and map.reverse_image / reverse_residual (clean
  // numbering) by the polished maps; the residual becomes the distance between a vertex's
  // deformed position and its image, divided by the target's diameter. map.c is kept.
  // An empty map.reverse_image asks for the forward map only (a part's reverse map marks
  // target vertices without a counterpart, which the nearest deformed vertex cannot).
  // Deterministic; `control` is checked between iterations. On control.threads, and
  // with the mirror repair (polish_with_mirror_repair) when the options ask for it.
  MirrorRepair apply(SpectralMap& map, const JobControl& control = {}) const;
  // The polish alone, on `threads` workers (0 = all cores) instead of control.threads (a
  // match that finishes several maps side by side shares its workers out among them).
  void polish(SpectralMap& map, const JobControl& control, int threads) const;
  // The polish from the map and, side by side, from the map with its mirrored segments
  // placed again (unfold_mirrors); the end state of lower energy is kept.
  MirrorRepair polish_with_mirror_repair(SpectralMap& map, const JobControl& control, int threads) const;
  // Only the mirror repair's first half: the map's mirrored segments placed again, their
  // vertices sent to the target vertices nearest their new positions; no polish, and
  // map.reverse_image / residuals are left as they were (for a map about to be refitted).
  MirrorRepair unfold_mirrors(SpectralMap& map) const;

 private:
  const PreprocessedShape& source_;
  const PreprocessedShape& target_;
  RigidityOptions options_;
  std::unique_ptr<const RigiditySystem> system_;  // null when options.iterations is 0
};

// One polish: RigidityPolish(source, target, options).apply(map, control).
MirrorRepair rigidity_polish(const PreprocessedShape& source, const PreprocessedShape& target,
                             const RigidityOptions& options, SpectralMap& map, const JobControl& control = {});

}  // namespace isocorr
