// The shared store's job queue (PgJobStore) in process, on a loopback PostgreSQL: claims
// never hand one job to two replicas, an expired lease passes the job on and the replica
// that lost it can no longer write it, attempts are bounded, a cancel is seen at renewal,
// the schema is created once however often replicas start, and results are served only to
// their job (those stored before manifests named their job are bound at the upgrade).
#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "loopback_postgres.h"
#include "postgres/pg_database.h"
#include "postgres/pg_job_store.h"
#include "service_error.h"
#include "storage/sealed_json.h"

namespace isocorr::testing {
namespace {

using server::JobRecord;
using server::JobState;
using std::chrono::milliseconds;

constexpr milliseconds kLongLease{600000};
constexpr milliseconds kExpiredLease{1};  // expired once a few milliseconds have passed

class PgJobQueue : public LoopbackPostgresTest {
 protected:
  void SetUp() override {
    LoopbackPostgresTest::SetUp();
    if (IsSkipped()) return;
    database_handle_ = std::make_unique<server::PgDatabase>(database_url());
    store_ = std::make_unique<server::PgJobStore>(*database_handle_);
  }
  JobRecord queued_job(int64_t create_time_ms) {
    JobRecord job;
    job.id = server::new_job_id();
    job.source_digest = std::string(64, 'a');
    job.target_digest = std::string(64, 'b');
    job.create_time_ms = create_time_ms;
    store_->insert(job, "creator");
    return job;
  }
  static void let_leases_expire() { std::this_thread::sleep_for(milliseconds(20)); }

  std::unique_ptr<server::PgDatabase> database_handle_;
  std::unique_ptr<server::PgJobStore> store_;
};

TEST_F(PgJobQueue, TwoReplicasClaimingAtOnceNeverTakeTheSameJob) {
  constexpr int kJobs = 24;
  std::set<std::string> queued;
  for (int i = 0; i < kJobs; ++i) queued.insert(queued_job(1000 + i).id);
  std::mutex mutex;
  std::multiset<std::string> claimed;
  auto claim_all = [&](const std::string& replica) {
    while (auto job = store_->claim(replica, kLongLease, 3)) {
      std::lock_guard lock(mutex);
      claimed.insert(job->id);
    }
  };
  std::thread first(claim_all, "replica-a"), second(claim_all, "replica-b");
  first.join();
  second.join();
  EXPECT_EQ(claimed.size(), static_cast<size_t>(kJobs));
  EXPECT_EQ(std::set<std::string>(claimed.begin(), claimed.end()), queued);
  for (const JobRecord& job : store_->list()) EXPECT_EQ(job.state, JobState::kRunning) << job.id;
}

TEST_F(PgJobQueue, AnExpiredLeasePassesTheJobOnAndTheFormerHolderCannotWriteIt) {
  const JobRecord queued = queued_job(1000);
  const auto first = store_->claim("replica-a", kExpiredLease, 3);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->attempts, 1);
  let_leases_expire();
  const auto second = store_->claim("replica-b", kLongLease, 3);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->id, queued.id);
  EXPECT_EQ(second->attempts, 2);

  // The former holder: no renewal, no end, no requeue.
  EXPECT_FALSE(store_->renew(queued.id, "replica-a", kLongLease, {}).held);
  JobRecord stale = *first;
  stale.state = JobState::kFailed;
  EXPECT_FALSE(store_->finish(stale, "replica-a", nullptr));
  store_->requeue(*first, "replica-a");
  EXPECT_EQ(store_->find(queued.id)->state, JobState::kRunning);

  // The new holder ends it, with its result, which reads back checked.
  MatchOutput output;
  output.forward = {1, 0, 2};
  output.reverse = {1, 0, 2};
  output.forward_confidence = output.reverse_confidence = {0.f, 0.f, 0.f};
  output.report_json = "{}";
  JobRecord done = *second;
  const server::EncodedResult result = server::encode_result(done, output);
  done.state = JobState::kSucceeded;
  EXPECT_TRUE(store_->renew(queued.id, "replica-b", kLongLease, {}).held);
  EXPECT_TRUE(store_->finish(done, "replica-b", &result));
  EXPECT_EQ(store_->find(queued.id)->state, JobState::kSucceeded);
  EXPECT_EQ(store_->read_map(done, ResultPart::kForwardMap), output.forward);
}

TEST_F(PgJobQueue, AJobWhoseReplicasKeepDyingFailsAfterMaxAttempts) {
  const JobRecord queued = queued_job(1000);
  ASSERT_TRUE(store_->claim("replica-a", kExpiredLease, 2).has_value());
  let_leases_expire();
  ASSERT_TRUE(store_->claim("replica-b", kExpiredLease, 2).has_value());
  let_leases_expire();
  EXPECT_FALSE(store_->claim("replica-c", kLongLease, 2).has_value());
  const JobRecord failed = *store_->find(queued.id);
  EXPECT_EQ(failed.state, JobState::kFailed);
  EXPECT_EQ(failed.error_code, server::ErrorCode::kAborted);
  EXPECT_EQ(failed.attempts, 2);
}

TEST_F(PgJobQueue, ACancelIsSeenByTheRunningReplicaAtItsNextRenewal) {
  const JobRecord queued = queued_job(1000);
  ASSERT_TRUE(store_->claim("replica-a", kLongLease, 3).has_value());
  EXPECT_FALSE(store_->renew(queued.id, "replica-a", kLongLease, {}).cancel_requested);
  EXPECT_EQ(store_->cancel(queued.id).state, JobState::kRunning);  // ends where it runs
  EXPECT_TRUE(store_->renew(queued.id, "replica-a", kLongLease, {}).cancel_requested);

  const JobRecord waiting = queued_job(2000);
  EXPECT_EQ(store_->cancel(waiting.id).state, JobState::kCancelled);  // never started: at once
  EXPECT_THROW(store_->cancel(waiting.id), server::ServiceError);       // already final
}

TEST_F(PgJobQueue, TheSchemaIsCreatedOnceHoweverOftenReplicasStart) {
  for (int i = 0; i < 3; ++i) server::PgDatabase again(database_url());
  EXPECT_EQ(sql("SELECT count(*), max(version) FROM isocorr_schema").out,
            "1|" + std::to_string(server::kPgSchemaVersion) + "\n");
  ASSERT_EQ(sql("UPDATE isocorr_schema SET version = 99").exit_code, 0);
  EXPECT_THROW(server::PgDatabase newer(database_url()), std::runtime_error);
}

TEST_F(PgJobQueue, AResultIsServedOnlyToItsJobAndOlderResultsAreBoundAtTheUpgrade) {
  queued_job(1000);
  JobRecord done = *store_->claim("replica-a", kLongLease, 3);
  MatchOutput output;
  output.forward = output.reverse = {1, 0};
  output.forward_confidence = output.reverse_confidence = {0.f, 0.f};
  output.report_json = "{}";
  const server::EncodedResult result = server::encode_result(done, output);
  done.state = JobState::kSucceeded;
  ASSERT_TRUE(store_->finish(done, "replica-a", &result));
  JobRecord other_settings = done;
  other_settings.settings.max_tracked += 1;
  EXPECT_THROW(store_->read_map(other_settings, ResultPart::kForwardMap), server::ServiceError);

  // As schema version 1 stored it: a manifest that names no job (the refusal above set the
  // result aside; the upgrade binds only results still in service).
  nlohmann::json manifest = result.manifest;
  manifest.erase("job");
  ASSERT_EQ(sql("UPDATE isocorr_results SET set_aside = NULL, manifest = $m$" + server::seal_json(manifest) +
                "$m$ WHERE job_id = '" + done.id + "'")
                .exit_code,
            0);
  EXPECT_THROW(store_->read_map(done, ResultPart::kForwardMap), server::ServiceError);  // unbound: not served
  ASSERT_EQ(sql("UPDATE isocorr_results SET set_aside = NULL").exit_code, 0);
  ASSERT_EQ(sql("UPDATE isocorr_schema SET version = 1").exit_code, 0);
  server::PgDatabase upgraded(database_url());
  EXPECT_EQ(store_->read_map(done, ResultPart::kForwardMap), output.forward);
  EXPECT_EQ(sql("SELECT version FROM isocorr_schema").out, std::to_string(server::kPgSchemaVersion) + "\n");
}

}  // namespace
}  // namespace isocorr::testing
