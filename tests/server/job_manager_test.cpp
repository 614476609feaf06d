// The job queue and its workers driven from several threads at once, as the API's handlers
// do: creates, cancels, listings and watchers race with two workers running jobs. Under
// scripts/sanitize.sh tsan this is the scheduler's race test; here it checks the outcome.
#include "jobs/job_manager.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <sstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "storage_test_support.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;


class JobManagerTest : public DataDirTest {
 protected:
  JobManagerTest() : DataDirTest("isocorr_job_manager_test_") {}
};

TEST_F(JobManagerTest, ConcurrentCallersAndWorkersAgreeOnEveryJob) {
  MeshStore meshes(dir_, int64_t{1} << 26);
  JobJournal journal(dir_);
  ShapeCache cache(int64_t{1} << 28);
  const TriangleMesh creature = limbed_blob(2);
  const std::string source = upload_mesh(meshes, off_text(creature), "creature.off").digest;
  const std::string target =
      upload_mesh(meshes, off_text(rotated_scaled_renumbered(creature, 1.3, 7).mesh), "moved.off").digest;

  JobManagerOptions options;
  options.workers = 2;
  JobManager manager(options, meshes, journal, cache);
  manager.recover_and_start();
  MatchSettings settings;
  settings.threads = 2;  // the engine's own threads inside each worker

  // Two callers create two jobs each; the second of each is cancelled at once, whether it
  // is still queued or already running (a running one may pass its last safe point first).
  std::vector<std::string> kept(2), cancelled(2);
  std::atomic<bool> done{false};
  std::atomic<int> listings{0};
  std::thread lister([&] {  // a client listing jobs all along
    while (!done) {
      for (const JobRecord& job : manager.list()) EXPECT_FALSE(job.id.empty());
      ++listings;
      std::this_thread::yield();
    }
  });
  std::vector<std::thread> callers;
  for (int i = 0; i < 2; ++i)
    callers.emplace_back([&, i] {
      kept[i] = manager.create(source, target, settings, "r1").id;
      cancelled[i] = manager.create(target, source, settings, "r2").id;
      const JobState at_cancel = manager.cancel(cancelled[i]).state;
      EXPECT_TRUE(at_cancel == JobState::kCancelled || at_cancel == JobState::kRunning ||
                  at_cancel == JobState::kSucceeded)
          << job_state_name(at_cancel);
      // Watch the kept job to its end, as `isocorr watch` does.
      uint64_t seen = 0;
      for (JobRecord job = manager.get(kept[i]); !is_final(job.state);) {
        seen = job.version;
        job = manager.wait_for_change(kept[i], seen, Clock::now() + std::chrono::seconds(1));
      }
    });
  for (auto& caller : callers) caller.join();
  for (const std::string& id : cancelled) {  // a running job stops at its next safe point
    for (JobRecord job = manager.get(id); !is_final(job.state);)
      job = manager.wait_for_change(id, job.version, Clock::now() + std::chrono::seconds(1));
  }
  done = true;
  lister.join();
  manager.shutdown();

  for (const std::string& id : kept) {
    const JobRecord job = manager.get(id);
    EXPECT_EQ(job.state, JobState::kSucceeded) << id << ": " << job.error_message;
    EXPECT_TRUE(journal.has_result(id));
  }
  int cancelled_count = 0;
  for (const std::string& id : cancelled) {
    const JobState state = manager.get(id).state;
    EXPECT_TRUE(state == JobState::kCancelled || state == JobState::kSucceeded) << id << ' ' << job_state_name(state);
    cancelled_count += state == JobState::kCancelled;
  }
  EXPECT_GT(cancelled_count, 0);
  EXPECT_GT(listings.load(), 0);
  // What the journal holds is what the manager reported.
  JobJournal reopened(dir_);
  EXPECT_EQ(reopened.load_all().size(), 4u);
}

}  // namespace
}  // namespace isocorr::server
