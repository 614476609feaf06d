#include "storage/job_record_json.h"

#include <cstdint>
#include <limits>
#include <stdexcept>

#include "isocorr/settings/settings_json.h"

namespace isocorr::server {
using nlohmann::json;

namespace {

JobState state_from_name(const std::string& name) {
  for (JobState s : {JobState::kQueued, JobState::kRunning, JobState::kSucceeded, JobState::kFailed, JobState::kCancelled})
    if (name == job_state_name(s)) return s;
  throw std::runtime_error("unknown job state '" + name + "'");
}

// A record's integers are read only when they fit their field: nlohmann's own conversion
// casts a JSON float or a wider integer as it is (undefined for 1e30; found by fuzzing).
template <typename Int>
Int integer_at(const json& j, const char* key) {
  const json& value = j.at(key);
  if (value.is_number_unsigned()) {
    if (value.get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<Int>::max()))
      return static_cast<Int>(value.get<uint64_t>());
  } else if (value.is_number_integer()) {
    const int64_t v = value.get<int64_t>();
    if (v >= std::numeric_limits<Int>::min() && v <= std::numeric_limits<Int>::max()) return static_cast<Int>(v);
  }
  throw std::runtime_error(std::string("'") + key + "' is not an integer of its field's range");
}

}  // namespace

json record_to_json(const JobRecord& job) {
  json timings = json::array();
  for (const auto& t : job.summary.timings) timings.push_back({{"stage", t.stage}, {"seconds", t.seconds}});
  return {{"id", job.id},
          {"state", job_state_name(job.state)},
          {"source", job.source_digest},
          {"target", job.target_digest},
          {"settings", settings_to_json(job.settings)},
          {"create_time_ms", job.create_time_ms},
          {"start_time_ms", job.start_time_ms},
          {"end_time_ms", job.end_time_ms},
          {"attempts", job.attempts},
          {"error_code", static_cast<int>(job.error_code)},
          {"error_message", job.error_message},
          {"created_by_request", job.created_by_request},
          {"summary",
           {{"source_vertices", job.summary.source_vertices},
            {"target_vertices", job.summary.target_vertices},
            {"diso", job.summary.diso},
            {"diso_max", job.summary.diso_max},
            {"dense_orientation", job.summary.dense_orientation},
            {"level0_maps", job.summary.level0_maps},
            {"tracked_maps", job.summary.tracked_maps},
            {"chosen_level0_rank", job.summary.chosen_level0_rank},
            {"timings", timings},
            {"notes", job.summary.notes},
            {"verdict", job.summary.verdict},
            {"verdict_reasons", job.summary.verdict_reasons}}}};
}

JobRecord record_from_json(const json& j) {
  JobRecord job;
  job.id = j.at("id");
  job.state = state_from_name(j.at("state"));
  job.source_digest = j.at("source");
  job.target_digest = j.at("target");
  job.settings = settings_from_json(j.at("settings"));
  job.create_time_ms = integer_at<int64_t>(j, "create_time_ms");
  job.start_time_ms = integer_at<int64_t>(j, "start_time_ms");
  job.end_time_ms = integer_at<int64_t>(j, "end_time_ms");
  job.attempts = integer_at<int>(j, "attempts");
  job.error_code = static_cast<ErrorCode>(integer_at<int>(j, "error_code"));
  job.error_message = j.at("error_message");
  // Records written before request ids were kept have none.
  if (j.contains("created_by_request")) job.created_by_request = j.at("created_by_request");
  const json& s = j.at("summary");
  job.summary.source_vertices = integer_at<int>(s, "source_vertices");
  job.summary.target_vertices = integer_at<int>(s, "target_vertices");
  job.summary.diso = s.at("diso");
  job.summary.diso_max = s.at("diso_max");
  job.summary.dense_orientation = s.at("dense_orientation");
  job.summary.level0_maps = integer_at<int>(s, "level0_maps");
  job.summary.tracked_maps = integer_at<int>(s, "tracked_maps");
  job.summary.chosen_level0_rank = integer_at<int>(s, "chosen_level0_rank");
  for (const auto& t : s.at("timings")) job.summary.timings.push_back({t.at("stage"), t.at("seconds")});
  job.summary.notes = s.at("notes").get<std::vector<std::string>>();
  // Records written before verdicts have none: "" says it was never given.
  if (s.contains("verdict")) {
    job.summary.verdict = s.at("verdict");
    job.summary.verdict_reasons = s.at("verdict_reasons").get<std::vector<std::string>>();
  }
  if (job.state == JobState::kSucceeded) job.progress = {"done", 0, 0, 1.0};
  return job;
}

}  // namespace isocorr::server
