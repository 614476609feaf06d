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
  // In a directory from before manifests were bound to their jobs (data_directory.h), its
  // results are adopted first (see adopt_legacy_results) and the layout marked current; in
  // any other, a result without a manifest is set aside in quarantine/results/.
  explicit JobJournal(const std::filesystem::path& data_dir);

  void save(const JobRecord& job);
  // Every record. An unreadable one is not dropped: it is copied to quarantine/jobs/ and
  // comes back as a FAILED job (error DATA_LOSS saying so), saved in its place. A result
  // without any record (the record was lost) is set aside likewise and its job comes back
  // the same way, so that it is reported rather than NOT_FOUND.
  std::vector<JobRecord> load_all();

  // results/<id>/ holds one file per part, named by result_part_name: little-endian int32
  // maps (.i32), float32 confidence (.f32), the report (.json), and manifest.json, which
  // names `job`. Written into a temporary directory and renamed into place, so a result
  // is whole or absent.
  void save_result(const JobRecord& job, const MatchOutput& result);
  bool has_result(const std::string& id) const;
  // Each read (ResultReader) checks the manifest against the job asking and the part
  // against the manifest (length, SHA-256) and a map's indices against the other mesh's
  // vertex count. A result that fails is moved to quarantine/results/; it and a missing
  // result throw ServiceError(kDataLoss).

 private:
  std::string read_checked_part(const JobRecord& job, ResultPart part) const override;
  // Results written before manifests were bound (once, at the upgrade): a result without
  // a manifest has its parts' structure checked and gets a manifest, a result whose
  // manifest names no job is bound to the record of its name. A result that fails is set
  // aside in quarantine/results/ (its job then answers DATA_LOSS on download).
  void adopt_legacy_results();
  // A current directory: a result whose manifest is missing is never given a new one
  // made from the parts it protects; it is set aside.
  void set_aside_results_without_manifest();
  [[noreturn]] void result_lost(const std::string& id, const std::string& problem) const;
  // A FAILED (DATA_LOSS) job in place of a record that is unreadable or lost, saved.
  JobRecord record_of_lost(const std::string& id, const std::filesystem::path& evidence, const std::string& message);

  std::filesystem::path jobs_dir_, results_dir_;
  Quarantine quarantine_;
};

}  // namespace isocorr::server
