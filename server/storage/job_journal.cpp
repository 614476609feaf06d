#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "storage/durable_file.h"
#include "storage/job_record_json.h"

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
