#include "storage/job_journal.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "isocorr/util/sha256.h"
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

template <typename T>
std::string to_bytes(const std::vector<T>& values) {  // little-endian hosts only (x86-64, arm64)
  std::string bytes(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}


constexpr const char* kManifestFile = "manifest.json";

template <typename T>
std::vector<T> from_bytes(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

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
      const std::vector<int> forward = from_bytes<int>(bytes[ResultPart::kForwardMap]);
      const std::vector<int> reverse = from_bytes<int>(bytes[ResultPart::kReverseMap]);
      // Without digests only the structure can be checked: whole int32/float32 arrays, one
      // confidence per map entry, every index inside the other map's length.
      bool whole = forward.size() * sizeof(int) == bytes[ResultPart::kForwardMap].size() &&
                   reverse.size() * sizeof(int) == bytes[ResultPart::kReverseMap].size() &&
                   bytes[ResultPart::kForwardConfidence].size() == forward.size() * sizeof(float) &&
                   bytes[ResultPart::kReverseConfidence].size() == reverse.size() * sizeof(float);
      for (const int index : forward) whole = whole && index >= 0 && index < static_cast<int64_t>(reverse.size());
      for (const int index : reverse) whole = whole && index >= 0 && index < static_cast<int64_t>(forward.size());
      if (!whole) throw std::runtime_error("its parts do not fit together");
      json parts = json::object();
      for (const auto& [part, content] : bytes)
        parts[std::string(result_part_name(part))] = {{"bytes", content.size()}, {"sha256", sha256_hex(content)}};
      write_file_durably(dir / kManifestFile, seal_json({{"source_vertices", forward.size()},
                                                         {"target_vertices", reverse.size()},
                                                         {"parts", parts}}));
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
    json parts = json::object();
    auto write_part = [&](ResultPart part, const std::string& bytes) {
      write_file_durably(temp_dir / part_file(part), bytes);
      parts[std::string(result_part_name(part))] = {{"bytes", bytes.size()}, {"sha256", sha256_hex(bytes)}};
    };
    write_part(ResultPart::kForwardMap, to_bytes(result.forward));
    write_part(ResultPart::kReverseMap, to_bytes(result.reverse));
    write_part(ResultPart::kForwardConfidence, to_bytes(result.forward_confidence));
    write_part(ResultPart::kReverseConfidence, to_bytes(result.reverse_confidence));
    write_part(ResultPart::kReport, result.report_json);
    const json manifest = {{"source_vertices", result.forward.size()},
                           {"target_vertices", result.reverse.size()},
                           {"parts", parts}};
    write_file_durably(temp_dir / kManifestFile, seal_json(manifest));
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
    const json& expected = manifest.at("parts").at(name);
    if (bytes.size() != expected.at("bytes").get<size_t>())
      result_lost(id, name + " has " + std::to_string(bytes.size()) + " bytes, not " +
                          std::to_string(expected.at("bytes").get<size_t>()));
    if (sha256_hex(bytes) != expected.at("sha256").get<std::string>()) result_lost(id, name + " does not match its sha256");
    if (part == ResultPart::kForwardMap || part == ResultPart::kReverseMap) {
      const bool forward = part == ResultPart::kForwardMap;
      const auto count = manifest.at(forward ? "source_vertices" : "target_vertices").get<size_t>();
      const auto limit = manifest.at(forward ? "target_vertices" : "source_vertices").get<int64_t>();
      const std::vector<int> map = from_bytes<int>(bytes);
      if (map.size() != count || bytes.size() % sizeof(int) != 0)
        result_lost(id, name + " has " + std::to_string(map.size()) + " entries for " + std::to_string(count) +
                            " vertices");
      for (const int index : map)
        if (index < 0 || index >= limit)
          result_lost(id, name + " holds index " + std::to_string(index) + ", outside the other mesh's " +
                              std::to_string(limit) + " vertices");
    }
  } catch (const json::exception& e) {
    result_lost(id, std::string("unreadable manifest: ") + e.what());
  }
  return bytes;
}

std::vector<int> JobJournal::read_map(const std::string& id, ResultPart part) const {
  return from_bytes<int>(read_checked_part(id, part));
}

std::vector<float> JobJournal::read_confidence(const std::string& id, ResultPart part) const {
  return from_bytes<float>(read_checked_part(id, part));
}

std::string JobJournal::read_report(const std::string& id) const { return read_checked_part(id, ResultPart::kReport); }

}  // namespace isocorr::server
