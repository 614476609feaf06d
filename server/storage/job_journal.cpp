#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "storage/durable_file.h"

namespace isocorr::server {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Every MatchSettings member, so a re-run after a restart uses exactly the same settings.
json settings_to_json(const MatchSettings& s) {
  return {{"level0_samples", s.level0_samples},
          {"level0_extra_targets", s.level0_extra_targets},
          {"max_level0_diso", s.max_level0_diso},
          {"max_level0_maps", s.max_level0_maps},
          {"min_tracked", s.min_tracked},
          {"max_tracked", s.max_tracked},
          {"selection", s.selection == SelectionRule::kLeastDistortion ? "least-diso" : "orientation"},
          {"orientation_threshold", s.orientation_threshold},
          {"orientation_margin", s.orientation_margin},
          {"orientation_weight", s.orientation_weight},
          {"handedness_guard", s.tracking.handedness_guard},
          {"anchor_cap", s.tracking.anchor_cap},
          {"trim_fraction", s.tracking.trim_fraction},
          {"window_factor", s.tracking.window_factor},
          {"dense_anchors", s.dense.anchor_count},
          {"dense_outliers", s.dense.outlier_fraction},
          {"dense_outlier_ratio", s.dense.outlier_ratio},
          {"dense_refinement_rounds", s.dense.anchor_refinement_rounds},
          {"dense_locality", s.dense.locality},
          {"level0_radius", s.preprocess.level0_radius},
          {"level_shrink", s.preprocess.level_shrink},
          {"decision_level", s.preprocess.decision_level},
          {"max_level0_samples", s.preprocess.max_level0_samples},
          {"agd_sources", s.preprocess.saliency.agd_sources},
          {"extremity_radius", s.preprocess.saliency.extremity_radius},
          {"threads", s.threads}};
}

MatchSettings settings_from_json(const json& j) {
  MatchSettings s;  // members missing from older records keep their defaults
  auto read = [&](const char* key, auto& member) {
    if (j.contains(key)) member = j.at(key).get<std::decay_t<decltype(member)>>();
  };
  read("level0_samples", s.level0_samples);
  read("level0_extra_targets", s.level0_extra_targets);
  read("max_level0_diso", s.max_level0_diso);
  read("max_level0_maps", s.max_level0_maps);
  read("min_tracked", s.min_tracked);
  read("max_tracked", s.max_tracked);
  if (j.value("selection", "orientation") == "least-diso") s.selection = SelectionRule::kLeastDistortion;
  read("orientation_threshold", s.orientation_threshold);
  read("orientation_margin", s.orientation_margin);
  read("orientation_weight", s.orientation_weight);
  read("handedness_guard", s.tracking.handedness_guard);
  read("anchor_cap", s.tracking.anchor_cap);
  read("trim_fraction", s.tracking.trim_fraction);
  read("window_factor", s.tracking.window_factor);
  read("dense_anchors", s.dense.anchor_count);
  read("dense_outliers", s.dense.outlier_fraction);
  read("dense_outlier_ratio", s.dense.outlier_ratio);
  read("dense_refinement_rounds", s.dense.anchor_refinement_rounds);
  read("dense_locality", s.dense.locality);
  read("level0_radius", s.preprocess.level0_radius);
  read("level_shrink", s.preprocess.level_shrink);
  read("decision_level", s.preprocess.decision_level);
  read("max_level0_samples", s.preprocess.max_level0_samples);
  read("agd_sources", s.preprocess.saliency.agd_sources);
  read("extremity_radius", s.preprocess.saliency.extremity_radius);
  read("threads", s.threads);
  return s;
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

void JobJournal::save_result(const std::string& id, const JobResultFiles& result) {
  const fs::path final_dir = results_dir_ / id, temp_dir = results_dir_ / (id + ".tmp");
  fs::remove_all(temp_dir);
  fs::create_directories(temp_dir);
  write_file_durably(temp_dir / "forward.i32", to_bytes(result.forward));
  write_file_durably(temp_dir / "reverse.i32", to_bytes(result.reverse));
  write_file_durably(temp_dir / "forward_confidence.f32", to_bytes(result.forward_confidence));
  write_file_durably(temp_dir / "reverse_confidence.f32", to_bytes(result.reverse_confidence));
  write_file_durably(temp_dir / "report.json", result.report_json);
  fs::remove_all(final_dir);
  fs::rename(temp_dir, final_dir);
  fsync_path(results_dir_);
}

bool JobJournal::has_result(const std::string& id) const { return fs::exists(results_dir_ / id / "report.json"); }

std::vector<int> JobJournal::read_indices(const std::string& id, const std::string& part) const {
  return from_bytes<int>(read_whole_file(results_dir_ / id / (part + ".i32")));
}

std::vector<float> JobJournal::read_values(const std::string& id, const std::string& part) const {
  return from_bytes<float>(read_whole_file(results_dir_ / id / (part + ".f32")));
}

std::string JobJournal::read_report(const std::string& id) const {
  return read_whole_file(results_dir_ / id / "report.json");
}

}  // namespace isocorr::server
