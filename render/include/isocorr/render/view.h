// Where a mesh is seen from: an orthographic camera, and the fit of a mesh into a
// rectangle of the picture.
#pragma once

#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

// A right-handed orthonormal frame (right x up = -forward), so a picture never shows a
// mirror image of the mesh.
struct ViewFrame {
  Vec3 right, up;
  Vec3 forward;  // from the eye into the scene
};

// The view names the `--view` option takes: "principal", or the side of the model the eye
// is on in the meshes' own coordinates: "+z" (front, +y up), "-z", "+x", "-x" (also +y up),
// "+y" (from above, -z up), "-y" (from below, +z up).
const std::vector<std::string>& view_names();

// "principal": the mesh's principal axes (vertex-area weighted), the longest one up, the
// shortest one towards the eye; each axis's sign makes the mesh's third moment along it
// positive, except the least skewed one, which follows from the handedness. The same
// shape moved rigidly is seen the same way. Otherwise the fixed frame named; throws
// InputError for an unknown name.
ViewFrame view_frame(const std::string& name, const TriangleMesh& mesh);

// How to look at the source of a map so as to see it as `target_frame` sees the target:
// up and the viewing direction are the source directions whose coordinates best predict
// (least squares, vertex-area weighted) the up and depth coordinates of each source
// vertex's image; right follows from handedness. Poses may differ, and a map that swaps
// left and right (a mirror-symmetric body's usual error) keeps up, front and back, so it
// shows as swapped colours rather than as a source turned round. Falls back to the
// source's principal view when the map predicts nothing (e.g. all to one vertex).
ViewFrame view_frame_through_map(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                                 const ViewFrame& target_frame);

// A mesh mapped into a rectangle of the picture: the picture's x = right, its y = -up, its
// depth along forward; as large as fits inside a margin, centred.
struct Rect {
  double x = 0, y = 0, width = 0, height = 0;
};
struct ScreenPoint {
  double x, y, depth;
};
std::vector<ScreenPoint> fit_into(const TriangleMesh& mesh, const ViewFrame& frame, const Rect& rect, double margin);

}  // namespace isocorr
