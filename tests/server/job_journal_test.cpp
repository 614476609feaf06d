// The job journal and result files: what a restarted server reads back is what was saved.
#include "storage/job_journal.h"

#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "storage_test_support.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;

class JobJournalTest : public DataDirTest {
 protected:
  JobJournalTest() : DataDirTest("isocorr_journal_test_") {}
};

TEST_F(JobJournalTest, RecordsAndResultsSurviveReopening) {
  JobRecord job;
  job.id = "0123456789abcdef";
  job.state = JobState::kSucceeded;
  job.source_digest = std::string(64, 'a');
  job.target_digest = std::string(64, 'b');
  job.settings.max_tracked = 17;
  job.settings.selection = SelectionRule::kLeastDistortion;
  job.settings.preprocess.level0_radius = 0.25;
  job.attempts = 2;
  job.summary.diso = 0.125;
  job.summary.timings = {{"dense", 1.5}};
  MatchOutput result;
  result.forward = {2, 0, 1};
  result.reverse = {1, 2, 0};
  result.forward_confidence = {0.5f, 0.25f, 0.125f};
  result.reverse_confidence = {0.f, 1.f, 2.f};
  result.report_json = "{\"final\":{}}";
  {
    JobJournal journal(dir_);
    journal.save_result(job, result);
    journal.save(job);
  }
  // A half-written result of a crash is swept away at start-up.
  fs::create_directories(dir_ / "results" / "deadbeef.tmp");

  JobJournal reopened(dir_);
  EXPECT_FALSE(fs::exists(dir_ / "results" / "deadbeef.tmp"));
  const std::vector<JobRecord> jobs = reopened.load_all();
  ASSERT_EQ(jobs.size(), 1u);
  const JobRecord& back = jobs[0];
  EXPECT_EQ(back.id, job.id);
  EXPECT_EQ(back.state, JobState::kSucceeded);
  EXPECT_EQ(back.target_digest, job.target_digest);
  EXPECT_EQ(back.settings.max_tracked, 17);
  EXPECT_EQ(back.settings.selection, SelectionRule::kLeastDistortion);
  EXPECT_DOUBLE_EQ(back.settings.preprocess.level0_radius, 0.25);
  EXPECT_EQ(back.attempts, 2);
  EXPECT_DOUBLE_EQ(back.summary.diso, 0.125);
  ASSERT_EQ(back.summary.timings.size(), 1u);
  EXPECT_EQ(back.summary.timings[0].stage, "dense");

  EXPECT_TRUE(reopened.has_result(job.id));
  EXPECT_EQ(reopened.read_map(job, ResultPart::kForwardMap), result.forward);
  EXPECT_EQ(reopened.read_map(job, ResultPart::kReverseMap), result.reverse);
  EXPECT_EQ(reopened.read_confidence(job, ResultPart::kForwardConfidence), result.forward_confidence);
  EXPECT_EQ(reopened.read_confidence(job, ResultPart::kReverseConfidence), result.reverse_confidence);
  EXPECT_EQ(reopened.read_report(job), result.report_json);
}

}  // namespace
}  // namespace isocorr::server
