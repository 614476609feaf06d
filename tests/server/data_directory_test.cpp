// The data directory's own rules: one server at a time (a lock naming its holder), results
// bound to their job and never given a new manifest made from the parts it protected
// (results from before manifests are adopted once, at the upgrade), and a mesh whose
// description was lost reported as DATA_LOSS and kept, never deleted.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "service_error.h"
#include "storage/data_directory.h"
#include "storage/durable_file.h"
#include "storage/job_journal.h"
#include "storage/sealed_json.h"
#include "storage_test_support.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;
using Kind = ServiceError::Kind;

class DataDirectory : public DataDirTest {
 protected:
  DataDirectory() : DataDirTest("isocorr_data_directory_test_") {}

  static MatchOutput result_of_size(int vertices) {
    MatchOutput result;
    for (int i = 0; i < vertices; ++i) {
      result.forward.push_back((i + 1) % vertices);
      result.reverse.push_back((i + vertices - 1) % vertices);
    }
    result.forward_confidence.assign(vertices, 0.5f);
    result.reverse_confidence.assign(vertices, 0.25f);
    result.report_json = "{\"vertices\":" + std::to_string(vertices) + "}";
    return result;
  }

  static JobRecord succeeded_job(const std::string& id, char mesh, int max_tracked) {
    JobRecord job;
    job.id = id;
    job.state = JobState::kSucceeded;
    job.source_digest = std::string(64, mesh);
    job.target_digest = std::string(64, static_cast<char>(mesh + 1));
    job.settings.max_tracked = max_tracked;
    return job;
  }

  // Saves the job's record and its result through a journal opened for the occasion.
  void store_job(const JobRecord& job, const MatchOutput& result) {
    JobJournal journal(dir_);
    journal.save(job);
    journal.save_result(job, result);
  }

  // ServiceError's kind and message, or kInvalidArgument and "" when `body` throws none.
  template <typename Body>
  static std::pair<Kind, std::string> thrown(Body body) {
    try {
      body();
    } catch (const ServiceError& e) {
      return {e.kind(), e.what()};
    }
    ADD_FAILURE() << "no ServiceError thrown";
    return {Kind::kInvalidArgument, ""};
  }
};

TEST_F(DataDirectory, ASecondHolderIsRefusedNamingTheFirstsPid) {
  fs::create_directories(dir_);
  {
    DataDirectoryLock held(dir_);
    std::string message;
    try {
      DataDirectoryLock second(dir_);  // flock: a second open file conflicts even in one process
      ADD_FAILURE() << "a second lock was granted";
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find("pid " + std::to_string(getpid())), std::string::npos) << message;
  }
  DataDirectoryLock again(dir_);  // released with its holder
}

TEST_F(DataDirectory, ALostManifestIsDataLossAndNeverMadeAgainFromTheParts) {
  const JobRecord job = succeeded_job("00000000000000a1", 'a', 8);
  store_job(job, result_of_size(4));
  // The manifest lost and a part corrupted meanwhile: a new manifest would launder it.
  fs::remove(dir_ / "results" / job.id / "manifest.json");
  std::string forward = read_whole_file(dir_ / "results" / job.id / "forward.i32");
  forward[0] = 3;
  std::ofstream(dir_ / "results" / job.id / "forward.i32", std::ios::binary) << forward;

  JobJournal journal(dir_);
  const auto [kind, message] = thrown([&] { journal.read_map(job, ResultPart::kForwardMap); });
  EXPECT_EQ(kind, Kind::kDataLoss);
  EXPECT_FALSE(fs::exists(dir_ / "results" / job.id / "manifest.json"));
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "results" / job.id / "forward.i32"));
  EXPECT_FALSE(journal.has_result(job.id));
}

TEST_F(DataDirectory, ResultsExchangedBetweenJobsAreDataLossForBoth) {
  const JobRecord first = succeeded_job("00000000000000b1", 'a', 8), second = succeeded_job("00000000000000b2", 'c', 9);
  store_job(first, result_of_size(4));
  store_job(second, result_of_size(4));  // same sizes: only the binding tells them apart
  const fs::path results = dir_ / "results";
  fs::rename(results / first.id, results / "swap");
  fs::rename(results / second.id, results / first.id);
  fs::rename(results / "swap", results / second.id);

  JobJournal journal(dir_);
  for (const JobRecord& job : {first, second}) {
    const auto [kind, message] = thrown([&] { journal.read_report(job); });
    EXPECT_EQ(kind, Kind::kDataLoss) << job.id;
    EXPECT_NE(message.find("made for jobs/"), std::string::npos) << message;
  }
}

TEST_F(DataDirectory, AResultIsServedOnlyToTheJobWithItsMeshesAndSettings) {
  const JobRecord job = succeeded_job("00000000000000c1", 'a', 8);
  for (const auto& [change, expected] :
       std::vector<std::pair<std::function<void(JobRecord&)>, std::string>>{
           {[](JobRecord& j) { j.settings.max_tracked = 9; }, "other settings"},
           {[](JobRecord& j) { j.target_digest = std::string(64, 'f'); }, "other meshes"}}) {
    store_job(job, result_of_size(3));
    JobRecord other = job;
    change(other);
    JobJournal journal(dir_);
    const auto [kind, message] = thrown([&] { journal.read_map(other, ResultPart::kReverseMap); });
    EXPECT_EQ(kind, Kind::kDataLoss);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST_F(DataDirectory, ManifestsFromBeforeTheBindingAreBoundAtTheUpgradeOnly) {
  const JobRecord job = succeeded_job("00000000000000d1", 'a', 8);
  store_job(job, result_of_size(5));
  // As the previous layout wrote it: a manifest naming no job, and no layout file.
  const fs::path manifest_path = dir_ / "results" / job.id / "manifest.json";
  nlohmann::json manifest = unseal_json(read_whole_file(manifest_path));
  manifest.erase("job");
  write_file_durably(manifest_path, seal_json(manifest));
  const std::string unbound = read_whole_file(manifest_path);
  fs::remove(dir_ / "layout");
  {
    JobJournal journal(dir_);
    EXPECT_EQ(journal.read_map(job, ResultPart::kForwardMap), result_of_size(5).forward);
  }
  // After the upgrade a manifest naming no job is not bound again: it is not served.
  write_file_durably(manifest_path, unbound);
  JobJournal journal(dir_);
  EXPECT_EQ(thrown([&] { journal.read_map(job, ResultPart::kForwardMap); }).first, Kind::kDataLoss);
}

TEST_F(DataDirectory, AMeshWhoseDescriptionIsLostIsQuarantinedAndDataLoss) {
  const std::string bytes = off_text(icosphere(2)), digest = sha256_hex(bytes);
  { MeshStore store(dir_, 1 << 24); upload_mesh(store, bytes, "ball.off"); }
  fs::remove(dir_ / "meshes" / (digest + ".json"));

  MeshStore store(dir_, 1 << 24);
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "meshes" / (digest + ".mesh")));  // kept, not deleted
  EXPECT_EQ(read_whole_file(dir_ / "quarantine" / "meshes" / (digest + ".mesh")), bytes);
  EXPECT_EQ(thrown([&] { store.describe(digest); }).first, Kind::kDataLoss);
  EXPECT_EQ(thrown([&] { store.get(digest); }).first, Kind::kDataLoss);
  upload_mesh(store, bytes, "ball.off");  // the repair, as for corrupted bytes
  EXPECT_EQ(store.read(digest).bytes, bytes);
}

TEST_F(DataDirectory, AStoreStoppedBetweenDescriptionAndBytesIsFinishedAtStart) {
  const std::string bytes = off_text(icosphere(2)), digest = sha256_hex(bytes);
  { MeshStore store(dir_, 1 << 24); upload_mesh(store, bytes, "ball.off"); }
  fs::rename(dir_ / "meshes" / (digest + ".mesh"), dir_ / "meshes" / (digest + ".mesh.pending"));
  MeshStore store(dir_, 1 << 24);
  EXPECT_EQ(store.read(digest).bytes, bytes);
  EXPECT_TRUE(store.remove(digest));
  EXPECT_TRUE(fs::is_empty(dir_ / "meshes"));
}

}  // namespace
}  // namespace isocorr::server
