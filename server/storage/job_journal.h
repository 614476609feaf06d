// The durable side of jobs under <data-dir>: jobs/<id>.json holds each job's record
// (rewritten atomically on every state change), results/<id>/ its finished result.
// A job is acknowledged (CreateMatchJob returns, or SUCCEEDED is reported) only after
// the corresponding write is on disk. Records are sealed (sealed_json.h) and each result
// has a manifest of its parts' lengths and SHA-256, so corruption is noticed when read.
// Writes throw ServiceError(kResourceExhausted) when the disk is full (storage_failure.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "isocorr/output/match_output.h"
#include "storage/job_record.h"
#include "storage/quarantine.h"
#include "storage/result_parts.h"

namespace isocorr::server {

class JobJournal final : public ResultReader {
 public:
  explicit JobJournal(const std::filesystem::path& data_dir);

  void save(const JobRecord& job);
  // Every record. An unreadable one is not dropped: it is copied to quarantine/jobs/ and
  // comes back as a FAILED job (error DATA_LOSS saying so), saved in its place.
  std::vector<JobRecord> load_all();

  // results/<id>/ holds one file per part, named by result_part_name: little-endian int32
  // maps (.i32), float32 confidence (.f32), the report (.json), and manifest.json. Written
  // into a temporary directory and renamed into place, so a result is whole or absent.
  void save_result(const std::string& id, const MatchOutput& result);
  bool has_result(const std::string& id) const;
  // Each read (ResultReader) checks the part against the manifest (length, SHA-256) and a
  // map's indices against the other mesh's vertex count. A result that fails is moved to
  // quarantine/results/; it and a missing result throw ServiceError(kDataLoss).

 private:
  std::string read_checked_part(const std::string& id, ResultPart part) const override;
  // Results written before manifests existed (their directory has none): the parts'
  // structure is checked once at start and a manifest written; a result that fails is
  // set aside in quarantine/results/ (its job then answers DATA_LOSS on download).
  void adopt_results_without_manifest();
  [[noreturn]] void result_lost(const std::string& id, const std::string& problem) const;
  JobRecord record_of_unreadable(const std::filesystem::path& path, const std::string& problem);

  std::filesystem::path jobs_dir_, results_dir_;
  Quarantine quarantine_;
};

}  // namespace isocorr::server
