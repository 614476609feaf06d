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

JobRecord succeeded_job(const std::string& id) {
  JobRecord job;
  job.id = id;
  job.state = JobState::kSucceeded;
  job.source_digest = std::string(64, 'a');
  job.target_digest = std::string(64, 'b');
  return job;
}

TEST_F(JobJournalTest, RecordsAndResultsSurviveReopening) {
  JobRecord job = succeeded_job("0123456789abcdef");
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
  result.forward_precise = {{4, {0.5f, 0.25f, 0.25f}}, {0, {1, 0, 0}}, {7, {0, 0, 1}}};
  result.reverse_precise = {{1, {0, 1, 0}}, {-1, {1, 0, 0}}, {2, {0.125f, 0.875f, 0}}};
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
  const PreciseMap precise = reopened.read_precise(job, ResultPart::kForwardPrecise);
  ASSERT_EQ(precise.size(), 3u);
  EXPECT_EQ(precise[0].face, 4);
  EXPECT_EQ(precise[0].weights, result.forward_precise[0].weights);
  EXPECT_EQ(reopened.read_precise(job, ResultPart::kReversePrecise)[1].face, -1);
}

// A result stored before precise maps has no such parts: asking for one is NOT_FOUND and
// leaves the result whole.
TEST_F(JobJournalTest, AResultWithoutPreciseMapsKeepsItsOtherParts) {
  const JobRecord job = succeeded_job("00000000000000aa");
  MatchOutput result;
  result.forward = {1, 0};
  result.reverse = {1, 0};
  result.forward_confidence = {0.f, 0.f};
  result.reverse_confidence = {0.f, 0.f};
  result.report_json = "{}";
  JobJournal journal(dir_);
  journal.save_result(job, result);
  journal.save(job);
  try {
    journal.read_precise(job, ResultPart::kForwardPrecise);
    ADD_FAILURE() << "read a part that was never stored";
  } catch (const ServiceError& e) {
    EXPECT_EQ(e.kind(), ServiceError::Kind::kNotFound);
    EXPECT_NE(std::string(e.what()).find("forward_precise"), std::string::npos) << e.what();
  }
  EXPECT_EQ(journal.read_map(job, ResultPart::kForwardMap), result.forward);
}

}  // namespace
}  // namespace isocorr::server
