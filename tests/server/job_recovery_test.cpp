// Recovery at start-up when the store was damaged meanwhile: a queued job whose mesh is now
// corrupted ends FAILED with DATA_LOSS (not NOT_FOUND, not run on other bytes).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "jobs/job_manager.h"
#include "storage/durable_file.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;

TEST(JobRecovery, QueuedJobOnACorruptedMeshFailsWithDataLoss) {
  const fs::path dir = fs::temp_directory_path() / ("isocorr_recovery_test_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const TriangleMesh mesh = icosphere(2);
  std::ostringstream off;
  off << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const Vec3& p : mesh.vertices) off << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Face& f : mesh.faces) off << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  const std::string bytes = off.str(), digest = sha256_hex(bytes);
  JobRecord job;
  job.id = "00000000000000dd";
  job.source_digest = job.target_digest = digest;
  {
    MeshStore store(dir, 1 << 24);
    auto upload = store.begin_upload(digest, "ball.off", static_cast<int64_t>(bytes.size()));
    upload->append(bytes);
    upload->commit();
    JobJournal(dir).save(job);  // QUEUED when the server stopped
  }
  std::string description = read_whole_file(dir / "meshes" / (digest + ".json"));
  description[description.size() / 2] ^= 0x01;
  std::ofstream(dir / "meshes" / (digest + ".json"), std::ios::binary) << description;

  MeshStore store(dir, 1 << 24);
  JobJournal journal(dir);
  ShapeCache cache(1 << 24);
  JobManager jobs({}, store, journal, cache);
  jobs.recover_and_start();
  const JobRecord recovered = jobs.get(job.id);
  EXPECT_EQ(recovered.state, JobState::kFailed);
  EXPECT_EQ(recovered.error_code, ErrorCode::kDataLoss);
  EXPECT_NE(recovered.error_message.find("upload the same file again"), std::string::npos) << recovered.error_message;
  jobs.shutdown();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isocorr::server
