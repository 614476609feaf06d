#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>

#include "service_error.h"
#include "storage/durable_file.h"
#include "storage/job_record_json.h"
#include "storage/sealed_json.h"
#include "storage/storage_failure.h"

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

constexpr const char* kManifestFile = "manifest.json";

}  // namespace

JobJournal::JobJournal(const fs::path& data_dir)
    : jobs_dir_(data_dir / "jobs"), results_dir_(data_dir / "results"), quarantine_(data_dir) {
  fs::create_directories(jobs_dir_);
  fs::create_directories(results_dir_);
  // Half-written results and records of a crashed run or a full disk; their jobs are re-run.
  for (const fs::path& dir : {results_dir_, jobs_dir_})
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().extension() == ".tmp") fs::remove_all(entry.path());
  adopt_results_without_manifest();
}

void JobJournal::adopt_results_without_manifest() {
  for (const auto& entry : fs::directory_iterator(results_dir_)) {
    const fs::path dir = entry.path();
    if (!entry.is_directory() || fs::exists(dir / kManifestFile)) continue;
    const std::string id = dir.filename().string();
    try {
      std::map<ResultPart, std::string> bytes;
      for (const ResultPart part : {ResultPart::kForwardMap, ResultPart::kReverseMap, ResultPart::kForwardConfidence,
                                    ResultPart::kReverseConfidence, ResultPart::kReport})
        bytes[part] = read_whole_file(dir / part_file(part));
      write_file_durably(dir / kManifestFile, seal_json(manifest_of_unchecked_parts(bytes)));
      spdlog::info("[job {}] result stored before manifests existed: structure checked, manifest written", id);
    } catch (const ServiceError&) {
      throw;  // the disk is full: leave the result as it is for the next start
    } catch (const std::exception& e) {
      quarantine_.set_aside("results", dir, std::string("result without manifest: ") + e.what());
    }
  }
}

void JobJournal::save(const JobRecord& job) {
  write_file_durably(jobs_dir_ / (job.id + ".json"), seal_json(record_to_json(job)));
}

JobRecord JobJournal::record_of_unreadable(const fs::path& path, const std::string& problem) {
  quarantine_.keep_copy("jobs", path, problem);
  JobRecord job;
  job.id = path.stem().string();
  job.state = JobState::kFailed;
  job.error_code = ErrorCode::kDataLoss;
  job.error_message = "the server's record of this job is corrupted on its disk (set aside for the operator); "
                      "its meshes, settings and result are unknown: submit the job again";
  std::error_code error;
  const auto modified = fs::last_write_time(path, error);
  job.create_time_ms = error ? now_ms()
                             : std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::file_clock::to_sys(modified).time_since_epoch())
                                   .count();
  job.end_time_ms = now_ms();
  try {
    save(job);  // replaces the unreadable record, whose copy is in quarantine
  } catch (const std::exception& e) {
    spdlog::error("[job {}] cannot replace its unreadable record: {}", job.id, e.what());
  }
  return job;
}

std::vector<JobRecord> JobJournal::load_all() {
  std::vector<JobRecord> jobs;
  for (const auto& entry : fs::directory_iterator(jobs_dir_)) {
    if (entry.path().extension() != ".json") continue;
    try {
      JobRecord job = record_from_json(unseal_json(read_whole_file(entry.path())));
      if (job.id != entry.path().stem().string()) throw std::runtime_error("it names another job");
      jobs.push_back(std::move(job));
    } catch (const std::exception& e) {
      jobs.push_back(record_of_unreadable(entry.path(), e.what()));
    }
  }
  return jobs;
}

void JobJournal::save_result(const std::string& id, const MatchOutput& result) {
  const fs::path final_dir = results_dir_ / id, temp_dir = results_dir_ / (id + ".tmp");
  try {
    guard_storage_write("cannot create", temp_dir, [&] {
      fs::remove_all(temp_dir);
      fs::create_directories(temp_dir);
    });
    const EncodedResult encoded = encode_result(result);
    for (const auto& [part, bytes] : encoded.parts) write_file_durably(temp_dir / part_file(part), bytes);
    write_file_durably(temp_dir / kManifestFile, seal_json(encoded.manifest));
    guard_storage_write("cannot move into place", final_dir, [&] {
      fs::remove_all(final_dir);
      fs::rename(temp_dir, final_dir);
    });
    fsync_path(results_dir_);
  } catch (...) {
    std::error_code ignored;  // a result is whole or absent
    fs::remove_all(temp_dir, ignored);
    throw;
  }
}

bool JobJournal::has_result(const std::string& id) const {
  return fs::exists(results_dir_ / id / kManifestFile);
}

void JobJournal::result_lost(const std::string& id, const std::string& problem) const {
  const fs::path dir = results_dir_ / id;
  if (fs::exists(dir)) quarantine_.set_aside("results", dir, problem);
  throw ServiceError(ServiceError::Kind::kDataLoss,
                     "the result of jobs/" + id + " is corrupted or missing on the server's disk (" + problem +
                         "); run the job again");
}

std::string JobJournal::read_checked_part(const std::string& id, ResultPart part) const {
  const fs::path dir = results_dir_ / id;
  json manifest;
  try {
    manifest = unseal_json(read_whole_file(dir / kManifestFile));
  } catch (const std::exception& e) {
    result_lost(id, fs::exists(dir) ? std::string("unreadable manifest: ") + e.what() : "no result stored");
  }
  const std::string name(result_part_name(part));
  std::string bytes;
  try {
    bytes = read_whole_file(dir / part_file(part));
  } catch (const std::exception&) {
    result_lost(id, name + " is missing");
  }
  try {
    const std::string problem = result_part_problem(manifest, part, bytes);
    if (!problem.empty()) result_lost(id, problem);
  } catch (const json::exception& e) {
    result_lost(id, std::string("unreadable manifest: ") + e.what());
  }
  return bytes;
}

}  // namespace isocorr::server
