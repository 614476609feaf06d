#include "isocorr/mesh/procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include <Eigen/Geometry>

namespace isocorr {

TriangleMesh icosphere(int level) {
  TriangleMesh mesh;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  for (const Vec3& p : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t),
                        Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1),
                        Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    mesh.vertices.push_back(p.normalized());
  mesh.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      return midpoint[key] = mesh.num_vertices() - 1;
    };
    std::vector<Face> faces;
    for (const Face& f : mesh.faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      faces.push_back({f[0], ab, ca});
      faces.push_back({f[1], bc, ab});
      faces.push_back({f[2], ca, bc});
      faces.push_back({ab, bc, ca});
    }
    mesh.faces.swap(faces);
  }
  return mesh;
}

TriangleMesh grid(int nx, int ny, double jitter, uint32_t seed) {
  TriangleMesh mesh;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> offset(-jitter, jitter);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const bool border = x == 0 || y == 0 || x == nx - 1 || y == ny - 1;
      const double dx = border ? 0 : offset(random), dy = border ? 0 : offset(random);
      mesh.vertices.push_back(Vec3(x + dx, y + dy, 0));
    }
  for (int y = 0; y + 1 < ny; ++y)
    for (int x = 0; x + 1 < nx; ++x) {
      const int a = y * nx + x, b = a + 1, c = a + nx, d = c + 1;
      mesh.faces.push_back({a, b, d});
      mesh.faces.push_back({a, d, c});
    }
  return mesh;
}

TriangleMesh limbed_blob(int level) {
  TriangleMesh mesh = icosphere(level);
  struct Limb {
    Vec3 direction;
    double length, width;
  };
  const Limb limbs[] = {{Vec3(1, 0.2, 0.1), 1.6, 0.35},  {Vec3(-0.3, 1, 0.2), 1.0, 0.30},
                        {Vec3(-0.6, -0.5, 0.6), 0.7, 0.45}, {Vec3(0.1, -0.4, -1), 1.3, 0.25},
                        {Vec3(0.2, 0.9, -0.7), 0.45, 0.40}};
  for (Vec3& p : mesh.vertices) {
    double radius = 1.0;
    for (const Limb& limb : limbs) {
      const double angle = std::acos(std::clamp(p.dot(limb.direction.normalized()), -1.0, 1.0));
      radius += limb.length * std::exp(-(angle * angle) / (limb.width * limb.width));
    }
    // A slight squash along z so the body itself has no rotational symmetry.
    p = Vec3(p.x() * radius, p.y() * radius * 0.9, p.z() * radius * 0.8);
  }
  return mesh;
}

TriangleMesh twofold_blob(int level) {
  // The icosphere's vertices are symmetric under the turn, and each limb has its turned
  // twin, so a vertex and its turned twin get the same radius (up to rounding).
  TriangleMesh mesh = icosphere(level);
  struct Limb {
    Vec3 direction;
    double length, width;
  };
  auto turned = [](const Limb& limb) {
    return Limb{Vec3(-limb.direction.x(), -limb.direction.y(), limb.direction.z()), limb.length, limb.width};
  };
  const Limb limbs[] = {{Vec3(1, 0.3, 0.2), 1.4, 0.35}, {Vec3(0.2, -1, -0.6), 0.8, 0.30}};
  const Limb head{Vec3(0, 0, 1), 0.5, 0.40};
  for (Vec3& p : mesh.vertices) {
    auto bump = [&p](const Limb& limb) {
      const double angle = std::acos(std::clamp(p.dot(limb.direction.normalized()), -1.0, 1.0));
      return limb.length * std::exp(-(angle * angle) / (limb.width * limb.width));
    };
    double radius = 1.0 + bump(head);
    for (const Limb& limb : limbs) radius += bump(limb) + bump(turned(limb));
    p = Vec3(p.x() * radius, p.y() * radius * 0.9, p.z() * radius * 0.8);
  }
  return mesh;
}

RenumberedCopy rotated_scaled_renumbered(const TriangleMesh& mesh, double scale, uint32_t seed) {
  std::mt19937 random(seed);
  RenumberedCopy copy;
  copy.permutation.resize(mesh.vertices.size());
  std::iota(copy.permutation.begin(), copy.permutation.end(), 0);
  std::shuffle(copy.permutation.begin(), copy.permutation.end(), random);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond(unit(random), unit(random), unit(random), unit(random)).normalized();
  copy.mesh.vertices.resize(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    copy.mesh.vertices[copy.permutation[i]] = scale * (rotation * mesh.vertices[i]) + Vec3(3, -2, 1);
  for (const Face& f : mesh.faces) {
    // Rotate the corner order too: same orientation, different first vertex.
    copy.mesh.faces.push_back({copy.permutation[f[1]], copy.permutation[f[2]], copy.permutation[f[0]]});
  }
  std::shuffle(copy.mesh.faces.begin(), copy.mesh.faces.end(), random);
  return copy;
}

}  // namespace isocorr
