// Job records read back from the journal's JSON: what the journal wrote comes back, and a
// number that does not fit its field makes the record unreadable instead of being cast.
#include "storage/job_record_json.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace isocorr::server {
namespace {

JobRecord sample_record() {
  JobRecord job;
  job.id = "0123456789abcdef";
  job.state = JobState::kFailed;
  job.source_digest = std::string(64, 'a');
  job.target_digest = std::string(64, 'b');
  job.create_time_ms = 1700000000123;
  job.attempts = 2;
  job.error_code = ErrorCode::kAborted;
  job.error_message = "gave up";
  job.summary.timings = {{"dense", 0.5}};
  job.created_by_request = "r42";
  job.settings.landmarks = {{3, 8}, {10, 2}};  // a restarted server reruns the job with them
  job.summary.verdict = "suspect";
  job.summary.verdict_reasons = {"a near tie"};
  return job;
}

TEST(JobRecordJson, RoundTripKeepsEveryStoredField) {
  const JobRecord back = record_from_json(record_to_json(sample_record()));
  EXPECT_EQ(back.id, "0123456789abcdef");
  EXPECT_EQ(back.state, JobState::kFailed);
  EXPECT_EQ(back.create_time_ms, 1700000000123);
  EXPECT_EQ(back.attempts, 2);
  EXPECT_EQ(back.error_code, ErrorCode::kAborted);
  EXPECT_EQ(back.error_message, "gave up");
  ASSERT_EQ(back.summary.timings.size(), 1u);
  EXPECT_EQ(back.summary.timings[0].stage, "dense");
  EXPECT_EQ(back.created_by_request, "r42");
  EXPECT_EQ(back.settings.landmarks, sample_record().settings.landmarks);
  EXPECT_EQ(back.summary.verdict, "suspect");
  EXPECT_EQ(back.summary.verdict_reasons, std::vector<std::string>{"a near tie"});
}

// Results stored before verdicts existed come back without one ("" is never a verdict).
TEST(JobRecordJson, RecordWithoutVerdictIsRead) {
  nlohmann::json older = record_to_json(sample_record());
  older["summary"].erase("verdict");
  older["summary"].erase("verdict_reasons");
  const JobRecord back = record_from_json(older);
  EXPECT_EQ(back.summary.verdict, "");
  EXPECT_TRUE(back.summary.verdict_reasons.empty());
}

// Records written before jobs kept the request that created them stay readable.
TEST(JobRecordJson, RecordWithoutCreatingRequestIsRead) {
  nlohmann::json older = record_to_json(sample_record());
  older.erase("created_by_request");
  const JobRecord back = record_from_json(older);
  EXPECT_EQ(back.id, "0123456789abcdef");
  EXPECT_EQ(back.created_by_request, "");
  EXPECT_EQ(job_tag(back), "job 0123456789abcdef");
  EXPECT_EQ(job_tag(sample_record()), "job 0123456789abcdef from r42");
}

// Found by fuzz/job_record_fuzzer.cpp with this record: nlohmann cast 1e30 to int64_t
// (undefined behaviour; the sanitizer build stops on it).
TEST(JobRecordJson, NumbersOutsideTheirFieldMakeTheRecordUnreadable) {
  const char* found =
      R"({"id":"x","state":"RUNNING","source":"","target":"","settings":{},"create_time_ms":1e30,)"
      R"("start_time_ms":0,"end_time_ms":0,"attempts":-1,"error_code":999,"error_message":"","summary":)"
      R"({"source_vertices":0,"target_vertices":0,"diso":0,"diso_max":0,"dense_orientation":0,)"
      R"("level0_maps":0,"tracked_maps":0,"chosen_level0_rank":0,"timings":[],"notes":[]}})";
  EXPECT_THROW(record_from_json(nlohmann::json::parse(found)), std::runtime_error);

  struct Case {
    const char* key;
    nlohmann::json value;
  };
  for (const Case& c : {Case{"start_time_ms", 2.5}, Case{"attempts", 4294967296LL}, Case{"attempts", 1e10},
                        Case{"error_code", -2147483649LL}, Case{"end_time_ms", 18446744073709551615ULL}}) {
    nlohmann::json record = record_to_json(sample_record());
    record[c.key] = c.value;
    EXPECT_THROW(record_from_json(record), std::runtime_error) << c.key << " = " << c.value;
  }
  nlohmann::json summary_record = record_to_json(sample_record());
  summary_record["summary"]["source_vertices"] = 3e9;
  EXPECT_THROW(record_from_json(summary_record), std::runtime_error);
}

}  // namespace
}  // namespace isocorr::server
