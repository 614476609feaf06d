#include "isocorr/render/view.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

ViewFrame frame_from(const Vec3& up, const Vec3& forward) { return {forward.cross(up), up, forward}; }

ViewFrame principal_frame(const TriangleMesh& mesh) {
  const std::vector<double> weights = vertex_areas(mesh);
  double total = 0;
  Vec3 centre = Vec3::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) total += weights[v], centre += weights[v] * mesh.vertices[v];
  if (!(total > 0)) return frame_from(Vec3::UnitY(), -Vec3::UnitZ());  // no area: nothing to orient by
  centre /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 d = mesh.vertices[v] - centre;
    covariance += weights[v] * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance / total);
  Eigen::Matrix3d axes = solver.eigenvectors();  // columns, variance ascending
  // Eigenvectors come with arbitrary signs: fix them by the shape's skewness, which moves
  // with the mesh. The long thin part hangs down (a standing person's legs) and reaches
  // towards the eye (feet point forwards). The least skewed axis is the one a nearly
  // symmetric body (left-right on a person) cannot orient, so it alone takes its sign from
  // right-handedness.
  std::array<double, 3> skew{};
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int a = 0; a < 3; ++a) skew[a] += weights[v] * std::pow(axes.col(a).dot(mesh.vertices[v] - centre), 3);
  skew[2] = -skew[2];  // the longest axis points up, away from its tail
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(skew[a]) < std::abs(skew[least])) least = a;
  for (int a = 0; a < 3; ++a)
    if (a != least && skew[a] < 0) axes.col(a) = -axes.col(a);
  if (axes.determinant() < 0) axes.col(least) = -axes.col(least);
  // Columns (shortest, middle, longest) are right-handed; the eye looks along -shortest.
  return frame_from(axes.col(2), -axes.col(0));
}

// The unit direction a in which a . (p - centre) best predicts values[v] over the mesh's
// vertices p (weights w), or zero when the values spread over no more than `negligible`.
Vec3 best_predicting_direction(const TriangleMesh& mesh, const std::vector<double>& weights,
                               const std::vector<double>& values, double negligible) {
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  if (values.empty() || !(*high - *low > negligible)) return Vec3::Zero();
  double total = 0, mean_value = 0;
  Vec3 centre = Vec3::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v)
    total += weights[v], centre += weights[v] * mesh.vertices[v], mean_value += weights[v] * values[v];
  if (!(total > 0)) return Vec3::Zero();
  centre /= total, mean_value /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Vec3 towards_values = Vec3::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 d = mesh.vertices[v] - centre;
    covariance += weights[v] * d * d.transpose();
    towards_values += weights[v] * d * (values[v] - mean_value);
  }
  const Vec3 a = covariance.ldlt().solve(towards_values);
  return a.allFinite() && a.norm() > 0 ? Vec3(a.normalized()) : Vec3::Zero();
}

}  // namespace

ViewFrame view_frame_through_map(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                                 const ViewFrame& target_frame) {
  const std::vector<double> weights = vertex_areas(source);
  std::vector<double> image_up(map.size()), image_depth(map.size());
  for (size_t v = 0; v < map.size(); ++v) {
    image_up[v] = target.vertices[map[v]].dot(target_frame.up);
    image_depth[v] = target.vertices[map[v]].dot(target_frame.forward);
  }
  double target_size = 0;
  for (const Vec3& p : target.vertices) target_size = std::max(target_size, (p - target.vertices[0]).norm());
  const double negligible = 1e-9 * target_size;  // images this close together say nothing
  const Vec3 up = best_predicting_direction(source, weights, image_up, negligible);
  Vec3 forward = best_predicting_direction(source, weights, image_depth, negligible);
  forward -= forward.dot(up) * up;
  if (up.isZero() || !(forward.norm() > 1e-6)) return principal_frame(source);
  return frame_from(up, forward.normalized());
}

const std::vector<std::string>& view_names() {
  static const std::vector<std::string> names = {"principal", "+z", "-z", "+x", "-x", "+y", "-y"};
  return names;
}

ViewFrame view_frame(const std::string& name, const TriangleMesh& mesh) {
  if (name == "principal") return principal_frame(mesh);
  if (name == "+z") return frame_from(Vec3::UnitY(), -Vec3::UnitZ());
  if (name == "-z") return frame_from(Vec3::UnitY(), Vec3::UnitZ());
  if (name == "+x") return frame_from(Vec3::UnitY(), -Vec3::UnitX());
  if (name == "-x") return frame_from(Vec3::UnitY(), Vec3::UnitX());
  if (name == "+y") return frame_from(-Vec3::UnitZ(), -Vec3::UnitY());
  if (name == "-y") return frame_from(Vec3::UnitZ(), Vec3::UnitY());
  throw InputError("unknown view '" + name.substr(0, 40) + "'");
}

std::vector<ScreenPoint> fit_into(const TriangleMesh& mesh, const ViewFrame& frame, const Rect& rect, double margin) {
  double low_x = std::numeric_limits<double>::max(), high_x = -low_x, low_y = low_x, high_y = -low_x;
  for (const Vec3& p : mesh.vertices) {
    low_x = std::min(low_x, p.dot(frame.right)), high_x = std::max(high_x, p.dot(frame.right));
    low_y = std::min(low_y, p.dot(frame.up)), high_y = std::max(high_y, p.dot(frame.up));
  }
  const double room_x = std::max(rect.width - 2 * margin, 1.0), room_y = std::max(rect.height - 2 * margin, 1.0);
  const double scale = std::min(room_x / std::max(high_x - low_x, 1e-12), room_y / std::max(high_y - low_y, 1e-12));
  const double mid_x = (low_x + high_x) / 2, mid_y = (low_y + high_y) / 2;
  std::vector<ScreenPoint> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices)
    points.push_back({rect.x + rect.width / 2 + (p.dot(frame.right) - mid_x) * scale,
                      rect.y + rect.height / 2 - (p.dot(frame.up) - mid_y) * scale, p.dot(frame.forward)});
  return points;
}

}  // namespace isocorr
