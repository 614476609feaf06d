// What the in-process storage tests share: a fresh data directory per test, a mesh as
// ASCII OFF bytes, and an upload straight into a MeshStore.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/util/sha256.h"
#include "storage/mesh_store.h"

namespace isocorr::server {

// dir_ is <tmp>/<prefix><pid>, empty at the start of each test and removed after it.
class DataDirTest : public ::testing::Test {
 protected:
  explicit DataDirTest(const std::string& prefix)
      : dir_(std::filesystem::temp_directory_path() / (prefix + std::to_string(getpid()))) {}
  void SetUp() override { std::filesystem::remove_all(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

inline std::string off_text(const TriangleMesh& mesh) {
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const Vec3& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return out.str();
}

inline MeshInfo upload_mesh(MeshStore& store, const std::string& bytes, const std::string& filename) {
  auto upload = store.begin_upload(sha256_hex(bytes), filename, static_cast<int64_t>(bytes.size()));
  upload->append(bytes);
  return upload->commit();
}

}  // namespace isocorr::server
