#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "isocorr/settings/settings_json.h"
#include "storage/durable_file.h"

namespace isocorr::server {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A result part's file under results/<id>/.
std::string part_file(ResultPart part) {
  const char* extension = part == ResultPart::kReport                                              ? ".json"
                          : part == ResultPart::kForwardMap || part == ResultPart::kReverseMap ? ".i32"
                                                                                                 : ".f32";
  return std::string(result_part_name(part)) + extension;
}

JobState state_from_name(const std::string& name) {
  for (JobState s : {JobState::kQueued, JobState::kRunning, JobState::kSucceeded, JobState::kFailed, JobState::kCancelled})
    if (name == job_state_name(s)) return s;
  throw std::runtime_error("unknown job state '" + name + "'");
}

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
            {"notes", job.summary.notes}}}};
}

JobRecord record_from_json(const json& j) {
  JobRecord job;
  job.id = j.at("id");
  job.state = state_from_name(j.at("state"));
  job.source_digest = j.at("source");
  job.target_digest = j.at("target");
  job.settings = settings_from_json(j.at("settings"));
  job.create_time_ms = j.at("create_time_ms");
  job.start_time_ms = j.at("start_time_ms");
  job.end_time_ms = j.at("end_time_ms");
  job.attempts = j.at("attempts");
  job.error_code = static_cast<ErrorCode>(j.at("error_code").get<int>());
  job.error_message = j.at("error_message");
  const json& s = j.at("summary");
  job.summary.source_vertices = s.at("source_vertices");
  job.summary.target_vertices = s.at("target_vertices");
  job.summary.diso = s.at("diso");
  job.summary.diso_max = s.at("diso_max");
  job.summary.dense_orientation = s.at("dense_orientation");
  job.summary.level0_maps = s.at("level0_maps");
  job.summary.tracked_maps = s.at("tracked_maps");
  job.summary.chosen_level0_rank = s.at("chosen_level0_rank");
  for (const auto& t : s.at("timings")) job.summary.timings.push_back({t.at("stage"), t.at("seconds")});
  job.summary.notes = s.at("notes").get<std::vector<std::string>>();
  if (job.state == JobState::kSucceeded) job.progress = {"done", 0, 0, 1.0};
  return job;
}

template <typename T>
std::string to_bytes(const std::vector<T>& values) {  // little-endian hosts only (x86-64, arm64)
  std::string bytes(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

template <typename T>
std::vector<T> from_bytes(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace

JobJournal::JobJournal(const fs::path& data_dir) : jobs_dir_(data_dir / "jobs"), results_dir_(data_dir / "results") {
  fs::create_directories(jobs_dir_);
  fs::create_directories(results_dir_);
  // Half-written results of a crashed run; their jobs are re-run.
  for (const auto& entry : fs::directory_iterator(results_dir_))
    if (entry.path().extension() == ".tmp") fs::remove_all(entry.path());
}

void JobJournal::save(const JobRecord& job) {
  write_file_durably(jobs_dir_ / (job.id + ".json"), record_to_json(job).dump(1));
}

std::vector<JobRecord> JobJournal::load_all() const {
  std::vector<JobRecord> jobs;
  for (const auto& entry : fs::directory_iterator(jobs_dir_)) {
    if (entry.path().extension() != ".json") continue;
    try {
      jobs.push_back(record_from_json(json::parse(read_whole_file(entry.path()))));
    } catch (const std::exception& e) {
      spdlog::error("skipping unreadable job record {}: {}", entry.path().string(), e.what());
    }
  }
  return jobs;
}

void JobJournal::save_result(const std::string& id, const MatchOutput& result) {
  const fs::path final_dir = results_dir_ / id, temp_dir = results_dir_ / (id + ".tmp");
  fs::remove_all(temp_dir);
  fs::create_directories(temp_dir);
  write_file_durably(temp_dir / part_file(ResultPart::kForwardMap), to_bytes(result.forward));
  write_file_durably(temp_dir / part_file(ResultPart::kReverseMap), to_bytes(result.reverse));
  write_file_durably(temp_dir / part_file(ResultPart::kForwardConfidence), to_bytes(result.forward_confidence));
  write_file_durably(temp_dir / part_file(ResultPart::kReverseConfidence), to_bytes(result.reverse_confidence));
  write_file_durably(temp_dir / part_file(ResultPart::kReport), result.report_json);
  fs::remove_all(final_dir);
  fs::rename(temp_dir, final_dir);
  fsync_path(results_dir_);
}

bool JobJournal::has_result(const std::string& id) const {
  return fs::exists(results_dir_ / id / part_file(ResultPart::kReport));
}

std::vector<int> JobJournal::read_map(const std::string& id, ResultPart part) const {
  return from_bytes<int>(read_whole_file(results_dir_ / id / part_file(part)));
}

std::vector<float> JobJournal::read_confidence(const std::string& id, ResultPart part) const {
  return from_bytes<float>(read_whole_file(results_dir_ / id / part_file(part)));
}

std::string JobJournal::read_report(const std::string& id) const {
  return read_whole_file(results_dir_ / id / part_file(ResultPart::kReport));
}

}  // namespace isocorr::server
