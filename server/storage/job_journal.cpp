#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "service_error.h"
#include "storage/data_directory.h"
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
  const char* extension = part == ResultPart::kReport                                                ? ".json"
                          : part == ResultPart::kForwardMap || part == ResultPart::kReverseMap     ? ".i32"
                          : part == ResultPart::kForwardPrecise || part == ResultPart::kReversePrecise ? ".points"
                                                                                                   : ".f32";
  return std::string(result_part_name(part)) + extension;
}

constexpr const char* kManifestFile = "manifest.json";

JobRecord read_record(const fs::path& path) {
  JobRecord job = record_from_json(unseal_json(read_whole_file(path)));
  if (job.id != path.stem().string()) throw std::runtime_error("it names another job");
  return job;
}

// The names new_job_id gives: anything else under results/ is no job's result.
bool is_job_id(const std::string& name) {
  return name.size() == 16 && name.find_first_not_of("0123456789abcdef") == std::string::npos;
}

}  // namespace

JobJournal::JobJournal(const fs::path& data_dir)
    : jobs_dir_(data_dir / "jobs"), results_dir_(data_dir / "results"), quarantine_(data_dir) {
  const bool legacy = predates_current_layout(data_dir);
  fs::create_directories(jobs_dir_);
  fs::create_directories(results_dir_);
  // Half-written results and records of a crashed run or a full disk; their jobs are re-run.
  for (const fs::path& dir : {results_dir_, jobs_dir_})
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().extension() == ".tmp") fs::remove_all(entry.path());
  if (legacy)
    adopt_legacy_results();
  else
    set_aside_results_without_manifest();
  mark_layout_current(data_dir);  // from now on nothing is adopted
}

void JobJournal::adopt_legacy_results() {
  for (const auto& entry : fs::directory_iterator(results_dir_)) {
    const fs::path dir = entry.path();
    const std::string id = dir.filename().string();
    // Without a readable record there is nothing to bind to: load_all reports the job.
    JobRecord job;
    try {
      if (!entry.is_directory()) continue;
      job = read_record(jobs_dir_ / (id + ".json"));
    } catch (const std::exception&) {
      continue;
    }
    try {
      if (fs::exists(dir / kManifestFile)) {
        json manifest = unseal_json(read_whole_file(dir / kManifestFile));
        if (manifest.contains("job")) continue;
        bind_manifest(manifest, job);
        write_file_durably(dir / kManifestFile, seal_json(manifest));
        spdlog::info("[job {}] result stored before manifests named their job: bound to its job", id);
        continue;
      }
      std::map<ResultPart, std::string> bytes;
      for (const ResultPart part : kFirstResultParts) bytes[part] = read_whole_file(dir / part_file(part));
      write_file_durably(dir / kManifestFile, seal_json(manifest_of_unchecked_parts(job, bytes)));
      spdlog::info("[job {}] result stored before manifests existed: structure checked, manifest written", id);
    } catch (const ServiceError&) {
      throw;  // the disk is full: leave the result as it is for the next start
    } catch (const std::exception& e) {
      quarantine_.set_aside("results", dir, std::string("result from before manifests: ") + e.what());
    }
  }
}

void JobJournal::set_aside_results_without_manifest() {
  for (const auto& entry : fs::directory_iterator(results_dir_))
    if (entry.is_directory() && !fs::exists(entry.path() / kManifestFile))
      quarantine_.set_aside("results", entry.path(),
                            "its manifest is missing, and a manifest is never made again from the parts it protects");
}

void JobJournal::save(const JobRecord& job) {
  write_file_durably(jobs_dir_ / (job.id + ".json"), seal_json(record_to_json(job)));
}

JobRecord JobJournal::record_of_lost(const std::string& id, const fs::path& evidence, const std::string& message) {
  JobRecord job;
  job.id = id;
  job.state = JobState::kFailed;
  job.error_code = ErrorCode::kDataLoss;
  job.error_message = message;
  std::error_code error;
  const auto modified = fs::last_write_time(evidence, error);
  job.create_time_ms = error ? now_ms()
                             : std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::file_clock::to_sys(modified).time_since_epoch())
                                   .count();
  job.end_time_ms = now_ms();
  try {
    save(job);
  } catch (const std::exception& e) {
    spdlog::error("[job {}] cannot record it as lost: {}", job.id, e.what());
  }
  return job;
}

std::vector<JobRecord> JobJournal::load_all() {
  std::vector<JobRecord> jobs;
  std::set<std::string> ids;
  for (const auto& entry : fs::directory_iterator(jobs_dir_)) {
    if (entry.path().extension() != ".json") continue;
    try {
      jobs.push_back(read_record(entry.path()));
    } catch (const std::exception& e) {
      quarantine_.keep_copy("jobs", entry.path(), e.what());  // replaced by the FAILED record below
      jobs.push_back(record_of_lost(entry.path().stem().string(), entry.path(),
                                    "the server's record of this job is corrupted on its disk (set aside for the "
                                    "operator); its meshes, settings and result are unknown: submit the job again"));
    }
    ids.insert(jobs.back().id);
  }
  for (const auto& entry : fs::directory_iterator(results_dir_)) {
    const std::string id = entry.path().filename().string();
    if (!entry.is_directory() || ids.count(id) || !is_job_id(id)) continue;
    spdlog::error("[job {}] its result is on disk but its record is lost", id);
    jobs.push_back(record_of_lost(id, entry.path(),
                                  "the server's record of this job is lost from its disk; its result was set aside "
                                  "for the operator, as nothing shows what it was made from: submit the job again"));
    // Once the FAILED record is on disk: until then the result is what shows the job existed.
    if (fs::exists(jobs_dir_ / (id + ".json"))) quarantine_.set_aside("results", entry.path(), "its job record is lost");
  }
  return jobs;
}

void JobJournal::save_result(const JobRecord& job, const MatchOutput& result) {
  const std::string& id = job.id;
  const fs::path final_dir = results_dir_ / id, temp_dir = results_dir_ / (id + ".tmp");
  try {
    guard_storage_write("cannot create", temp_dir, [&] {
      fs::remove_all(temp_dir);
      fs::create_directories(temp_dir);
    });
    const EncodedResult encoded = encode_result(job, result);
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

std::string JobJournal::read_checked_part(const JobRecord& job, ResultPart part) const {
  const std::string& id = job.id;
  const fs::path dir = results_dir_ / id;
  json manifest;
  try {
    manifest = unseal_json(read_whole_file(dir / kManifestFile));
  } catch (const std::exception& e) {
    result_lost(id, fs::exists(dir)                    ? std::string("unreadable manifest: ") + e.what()
                    : quarantine_.holds("results", id) ? "it was set aside as corrupted"
                                                       : "no result stored");
  }
  try {
    const std::string problem = result_binding_problem(manifest, job);
    if (!problem.empty()) result_lost(id, problem);
  } catch (const json::exception& e) {
    result_lost(id, std::string("unreadable manifest: ") + e.what());
  }
  if (!manifest_holds(manifest, part)) throw PartNotStored(id, part);
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
