// Recovery at start-up when the store was damaged meanwhile: a queued job whose mesh is now
// corrupted ends FAILED with DATA_LOSS (not NOT_FOUND, not run on other bytes); a job that
// stopped the server twice is not run a third time; a job seen finished stays so.
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "jobs/job_manager.h"
#include "storage/durable_file.h"
#include "storage_test_support.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;

class JobRecovery : public DataDirTest {
 protected:
  JobRecovery() : DataDirTest("isocorr_job_recovery_test_") {}

  // Job `id` as a server with the default options finds it when it starts.
  JobRecord recovered(const std::string& id) {
    MeshStore store(dir_, 1 << 24);
    JobJournal journal(dir_);
    ShapeCache cache(1 << 24);
    JobManager jobs({}, store, journal, cache);
    jobs.recover_and_start();
    const JobRecord job = jobs.get(id);
    jobs.shutdown();
    return job;
  }
};

TEST_F(JobRecovery, QueuedJobOnACorruptedMeshFailsWithDataLoss) {
  const std::string bytes = off_text(icosphere(2)), digest = sha256_hex(bytes);
  JobRecord job;
  job.id = "00000000000000dd";
  job.source_digest = job.target_digest = digest;
  {
    MeshStore store(dir_, 1 << 24);
    upload_mesh(store, bytes, "ball.off");
    JobJournal(dir_).save(job);  // QUEUED when the server stopped
  }
  std::string description = read_whole_file(dir_ / "meshes" / (digest + ".json"));
  description[description.size() / 2] ^= 0x01;
  std::ofstream(dir_ / "meshes" / (digest + ".json"), std::ios::binary) << description;

  const JobRecord after = recovered(job.id);
  EXPECT_EQ(after.state, JobState::kFailed);
  EXPECT_EQ(after.error_code, ErrorCode::kDataLoss);
  EXPECT_NE(after.error_message.find("upload the same file again"), std::string::npos) << after.error_message;
}

TEST_F(JobRecovery, AJobThatStoppedTheServerTwiceIsNotRunAThirdTime) {
  JobRecord job;
  job.id = "00000000000000e2";
  job.source_digest = job.target_digest = std::string(64, 'a');
  job.state = JobState::kRunning;  // running at the server's second unclean stop
  job.attempts = 2;
  JobJournal(dir_).save(job);

  const JobRecord after = recovered(job.id);
  EXPECT_EQ(after.state, JobState::kFailed);
  EXPECT_EQ(after.error_code, ErrorCode::kAborted);
  EXPECT_NE(after.error_message.find("stopped the server twice"), std::string::npos) << after.error_message;
}

// The store's meshes, except that reading one waits until `open` is called: the job
// reading it is RUNNING, its start on disk, until the test lets it go on.
class GatedMeshes final : public MeshRepository {
 public:
  explicit GatedMeshes(MeshRepository& inner) : inner_(inner) {}
  void wait_until_read() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return reading_; });
  }
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }

  std::unique_ptr<MeshUpload> begin_upload(const std::string& digest, const std::string& filename,
                                           int64_t declared_size) override {
    return inner_.begin_upload(digest, filename, declared_size);
  }
  std::optional<MeshInfo> describe(const std::string& digest) override { return inner_.describe(digest); }
  std::optional<MeshInfo> get(const std::string& digest) override { return inner_.get(digest); }
  std::optional<MeshInfo> find_intact(const std::string& digest) override { return inner_.find_intact(digest); }
  std::vector<MeshInfo> list() override { return inner_.list(); }
  bool remove(const std::string& digest) override { return inner_.remove(digest); }
  StoredMesh read(const std::string& digest) override {
    std::unique_lock lock(mutex_);
    reading_ = true;
    changed_.notify_all();
    changed_.wait(lock, [&] { return open_; });
    lock.unlock();
    return inner_.read(digest);
  }
  int64_t max_mesh_bytes() const override { return inner_.max_mesh_bytes(); }

 private:
  MeshRepository& inner_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool reading_ = false, open_ = false;
};

// The job as `jobs` shows it once `done` holds for it (the test fails after a minute).
template <typename Done>
JobRecord wait_until(const JobManager& jobs, const std::string& id, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
  JobRecord job = jobs.get(id);
  while (!done(job) && std::chrono::steady_clock::now() < deadline)
    job = jobs.wait_for_change(id, job.version, deadline);
  EXPECT_TRUE(done(job)) << job_state_name(job.state) << " " << job.progress.stage;
  return job;
}

TEST_F(JobRecovery, AJobSeenFinishedIsNotRunAgainAfterARestart) {
  std::string id;
  JobRecord seen, finished;
  {
    MeshStore store(dir_, 1 << 24);
    const std::string digest = upload_mesh(store, off_text(icosphere(2)), "ball.off").digest;
    JobJournal journal(dir_);
    ShapeCache cache(1 << 24);
    GatedMeshes gated(store);
    JobManager jobs({}, gated, journal, cache);
    jobs.recover_and_start();
    id = jobs.create(digest, digest, MatchSettings{}, "request").id;
    gated.wait_until_read();
    // The disk refuses the job's end: its record's temporary name is taken by a directory.
    fs::create_directories(dir_ / "jobs" / (id + ".json.tmp"));
    gated.open();
    seen = wait_until(jobs, id, [](const JobRecord& job) {
      return is_final(job.state) || job.progress.stage == "waiting for disk space to record its end";
    });
    EXPECT_EQ(seen.state, JobState::kRunning);  // not shown done while its end is not on disk
    fs::remove(dir_ / "jobs" / (id + ".json.tmp"));  // space again
    finished = wait_until(jobs, id, [](const JobRecord& job) { return is_final(job.state); });
    jobs.shutdown();
  }
  const JobRecord after = recovered(id);
  EXPECT_EQ(after.state, finished.state);
  EXPECT_EQ(after.attempts, finished.attempts);
  if (is_final(seen.state)) EXPECT_EQ(after.state, seen.state);
}

}  // namespace
}  // namespace isocorr::server
