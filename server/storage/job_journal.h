// The durable side of jobs under <data-dir>: jobs/<id>.json holds each job's record
// (rewritten atomically on every state change), results/<id>/ its finished result.
// A job is acknowledged (CreateMatchJob returns, or SUCCEEDED is reported) only after
// the corresponding write is on disk.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "isocorr/output/match_output.h"
#include "storage/job_record.h"

namespace isocorr::server {

class JobJournal {
 public:
  explicit JobJournal(const std::filesystem::path& data_dir);

  void save(const JobRecord& job);
  std::vector<JobRecord> load_all() const;  // skips unreadable records (logged)

  // results/<id>/ holds one file per part, named by result_part_name: little-endian int32
  // maps (.i32), float32 confidence (.f32), the report (.json). Written into a temporary
  // directory and renamed into place, so a result is whole or absent.
  void save_result(const std::string& id, const MatchOutput& result);
  bool has_result(const std::string& id) const;
  std::vector<int> read_map(const std::string& id, ResultPart part) const;           // kForwardMap, kReverseMap
  std::vector<float> read_confidence(const std::string& id, ResultPart part) const;  // k*Confidence
  std::string read_report(const std::string& id) const;

 private:
  std::filesystem::path jobs_dir_, results_dir_;
};

}  // namespace isocorr::server
